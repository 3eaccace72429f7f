//! Perception: what an agent reads from an all-around scan of the world (seed 000 §3.1) —
//! the free distance along each ray, for the agent's centre and for its whole disc
//! ([`swept_free`]), the heading toward the goal that TangentBug's motion-to-goal takes
//! ([`heading_to_goal`]), whether the straight way to the goal is open ([`goal_visible`]) and
//! how near the goal the obstacle boundary around the agent comes
//! ([`obstacle_goal_distance`]).
//!
//! Below the simulation loop, the controller, the boundary follower and the memory, which all
//! read the scan through these functions. Pure functions of their arguments, plus the shared
//! ray directions of [`Fan`].

use glam::DVec2;

use crate::world::{SectorLayout, World};

/// The smallest distance from `goal` to an obstacle point hit by the `scan` with a free
/// distance below `range` (the obstacle boundary around the agent), metres; infinite when no
/// ray hit anything that near.
pub fn obstacle_goal_distance(scan: &[f64], from: DVec2, goal: DVec2, radius: f64, range: f64) -> f64 {
    let fan = Fan::of(scan.len());
    scan.iter()
        .enumerate()
        .filter(|(_, f)| **f < range)
        .map(|(i, f)| {
            let hit = from + fan.rays[i] * (f + radius);
            hit.distance(goal)
        })
        .fold(f64::INFINITY, f64::min)
}

/// How far ahead the straight way to the goal must be free to count as open, metres.
pub const GOAL_LOOKAHEAD_M: f64 = 2.0;

/// True when a disc of `radius` could move straight from `from` toward `goal` over the next
/// `min(distance, range, GOAL_LOOKAHEAD_M)` metres without touching an obstacle (three
/// parallel rays).
pub fn goal_visible(
    world: &World,
    from: DVec2,
    goal: DVec2,
    radius: f64,
    layout: &SectorLayout,
    scratch: &mut Vec<usize>,
) -> bool {
    let d = from.distance(goal);
    if d <= 1e-9 {
        return true;
    }
    let dir = (goal - from) / d;
    let reach = d.min(layout.range).min(GOAL_LOOKAHEAD_M);
    let side = dir.perp() * radius;
    [from, from + side, from - side].iter().all(|&o| world.ray_cast(o, dir, reach, scratch).is_none())
}

/// Free distance for the agent's disc along `n` rays evenly spaced around it (ray `i` at
/// angle `2πi/n`): the distance from `from` to the first obstacle or other agent the ray hits,
/// less `radius`, capped at `range`, metres. `walls` gets the same for the world's obstacles
/// alone (what the agent's memory keeps).
#[allow(clippy::too_many_arguments)]
pub fn scan(
    world: &World,
    from: DVec2,
    radius: f64,
    n: usize,
    range: f64,
    others: &[(DVec2, f64)],
    scratch: &mut Vec<usize>,
    out: &mut Vec<f64>,
    walls: &mut Vec<f64>,
) {
    out.clear();
    walls.clear();
    let fan = Fan::of(n.max(1));
    world.ray_fan(from, &fan.rays, range + radius, scratch, walls);
    for (k, &dir) in fan.rays.iter().enumerate() {
        let mut t = walls[k].min(range + radius);
        walls[k] = (t - radius).clamp(0.0, range);
        for &(c, r) in others {
            if let Ok(disc) = crate::geom::Shape::circle(c, r)
                && let Some(h) = disc.ray_cast(from, dir, t)
            {
                t = t.min(h);
            }
        }
        out.push((t - radius).clamp(0.0, range));
    }
}

/// How far the agent's whole disc (not just its centre) can travel along each ray of an
/// all-around `scan`: a hit point of another ray blocks a direction when it lies within
/// `radius` of the line the disc's centre sweeps. Same layout as `scan`, metres.
pub fn swept_free(scan: &[f64], radius: f64, range: f64) -> Vec<f64> {
    let n = scan.len();
    let fan = Fan::of(n.max(1));
    let step = std::f64::consts::TAU / n.max(1) as f64;
    // Each hit point blocks only the rays within its angular reach of the disc: visit those
    // (a ray more for rounding) instead of every pair of rays. The least of the same cuts, so
    // the same as [`swept_free_along`] on every ray.
    let mut free = scan.to_vec();
    for (j, &f) in scan.iter().enumerate() {
        if f >= range {
            continue;
        }
        let t = f + radius;
        let reach = if radius < t { ((radius / t).asin() / step).ceil() as usize + 1 } else { n / 4 + 1 };
        let reach = reach.min(n.saturating_sub(1) / 2) as isize;
        for e in -reach..=reach {
            let d = e.rem_euclid(n as isize) as usize;
            let (c, s) = fan.turns[d];
            let (along, perp) = (t * c, t * s);
            if along > 0.0 && perp.abs() < radius {
                let i = (j + n - d) % n;
                free[i] = free[i].min((along - (radius * radius - perp * perp).sqrt()).max(0.0));
            }
        }
    }
    free
}

/// The directions of an all-around scan of `n` rays, computed once per ray count and shared:
/// `rays[k]` is the unit vector of ray `k` (absolute angle `2πk/n`), `turns[d]` the cosine and
/// sine of `d` ray steps (`d · 2π/n`).
#[derive(Debug)]
pub struct Fan {
    /// Unit direction of each ray.
    pub rays: Vec<DVec2>,
    /// Cosine and sine of each whole number of ray steps.
    pub turns: Vec<(f64, f64)>,
}

impl Fan {
    fn new(n: usize) -> Fan {
        let step = std::f64::consts::TAU / n as f64;
        Fan {
            rays: (0..n).map(|i| DVec2::from_angle(std::f64::consts::TAU * i as f64 / n as f64)).collect(),
            turns: (0..n).map(|d| ((step * d as f64).cos(), (step * d as f64).sin())).collect(),
        }
    }

    /// The fan of `n` rays (at least one), built on first use.
    pub fn of(n: usize) -> std::sync::Arc<Fan> {
        thread_local! {
            static LAST: std::cell::RefCell<Option<std::sync::Arc<Fan>>> = const { std::cell::RefCell::new(None) };
        }
        let n = n.max(1);
        LAST.with(|last| {
            let mut last = last.borrow_mut();
            match &*last {
                Some(fan) if fan.rays.len() == n => fan.clone(),
                _ => {
                    let fan = std::sync::Arc::new(Fan::new(n));
                    *last = Some(fan.clone());
                    fan
                }
            }
        })
    }
}

/// How far a disc of radius `grown`, centred where `scan` was taken, can travel along ray `i`
/// of it: the scan's own free distance, cut where a hit point of another ray (at its free
/// distance plus `radius`) comes within `grown` of the line swept, metres. `dir(d)` is the
/// cosine and sine of `d` ray steps.
pub fn swept_free_along(
    scan: &[f64],
    i: usize,
    radius: f64,
    grown: f64,
    range: f64,
    dir: impl Fn(usize) -> (f64, f64),
) -> f64 {
    let n = scan.len();
    let mut free = scan[i];
    for (j, &f) in scan.iter().enumerate() {
        if f >= range {
            continue;
        }
        let t = f + radius;
        let (c, s) = dir((j + n - i) % n);
        let (along, perp) = (t * c, t * s);
        if along > 0.0 && perp.abs() < grown {
            free = free.min((along - (grown * grown - perp * perp).sqrt()).max(0.0));
        }
    }
    free
}

/// [`swept_free_along`] with the ray steps' cosines and sines `turns` (as [`Fan::turns`]),
/// visiting only the rays within a quarter turn and a ray of ray `i`: a hit point further round
/// lies behind the disc (its cosine is below zero by more than rounding) and cuts nothing, so
/// the result is the same, bit for bit.
pub fn swept_free_ahead(scan: &[f64], i: usize, radius: f64, grown: f64, range: f64, turns: &[(f64, f64)]) -> f64 {
    let n = scan.len();
    let half = n / 4 + 1;
    if 2 * half + 1 >= n {
        return swept_free_along(scan, i, radius, grown, range, |d| turns[d]);
    }
    let mut free = scan[i];
    // The rays `d` steps round from ray `i` for `d` in `d0..d1`, in that order, as at most two
    // runs of neighbouring rays (the scan wraps round).
    let mut cut = |d0: usize, d1: usize| {
        let mut d = d0;
        while d < d1 {
            let j = (i + d) % n;
            let len = (d1 - d).min(n - j);
            for (&f, &(c, s)) in scan[j..j + len].iter().zip(&turns[d..d + len]) {
                if f >= range {
                    continue;
                }
                let t = f + radius;
                let (along, perp) = (t * c, t * s);
                if along > 0.0 && perp.abs() < grown {
                    free = free.min((along - (grown * grown - perp * perp).sqrt()).max(0.0));
                }
            }
            d += len;
        }
    };
    cut(0, half + 1);
    cut(n - half, n);
    free
}

/// The absolute heading toward the goal given an all-around `scan`, and the closest approach
/// to the goal reachable in a straight line: straight at the goal when the way is open far
/// enough, else the free direction whose reachable end point minimises "distance to the end
/// point + end point to goal" (TangentBug's motion-to-goal choice). Free distances are those
/// of the agent's whole disc ([`swept_free`]).
pub fn heading_to_goal(scan: &[f64], from: DVec2, goal: DVec2, radius: f64, range: f64) -> (f64, f64) {
    let n = scan.len();
    let direct = (goal - from).to_angle();
    let d_goal = from.distance(goal);
    if n == 0 {
        return (direct, d_goal);
    }
    let fan = Fan::of(n);
    let step = std::f64::consts::TAU / n as f64;
    let gi = ((direct.rem_euclid(std::f64::consts::TAU) / step).round() as usize) % n;
    // The ray toward the goal alone first (what `swept_free` gives on it); all of them only
    // when the goal is not in the clear.
    let ahead = swept_free_ahead(scan, gi, radius, radius, range, &fan.turns);
    if ahead >= d_goal.min(range) - 1e-9 {
        let reachable = if ahead >= d_goal { 0.0 } else { d_goal - ahead };
        return (direct, reachable);
    }
    let free = swept_free(scan, radius, range);
    let mut best = (f64::INFINITY, direct);
    let mut reachable = d_goal;
    for (i, &f) in free.iter().enumerate() {
        if f < 0.3 {
            continue;
        }
        let angle = step * i as f64;
        let reach = f.min(d_goal);
        let (c, s) = fan.turns[i];
        let end = from + DVec2::new(c, s) * reach;
        reachable = reachable.min(end.distance(goal));
        let h = reach + end.distance(goal);
        if h < best.0 {
            best = (h, angle);
        }
    }
    (best.1, reachable)
}
