//! Pieces shared by the generators built on a grid of cells (rooms, maze, grid maps): random
//! integers and shuffles drawn from a [`crate::rng`] stream, graph searches over cell
//! adjacency lists, axis-aligned wall boxes, and the final solvability check.
//!
//! Everything is deterministic: adjacency lists are plain vectors visited in order, ties are
//! broken by the lowest index, and randomness comes only from the stream passed in.

use glam::DVec2;
use rand_chacha::ChaCha8Rng;

use super::generate::connected;
use crate::rng;
use crate::scenario::Scenario;
use crate::world::obstacle::DEFAULT_Z;
use crate::world::{Obstacle, ObstacleShape};

/// A uniform index in `0..n` (0 when `n` is 0).
pub(crate) fn index(rng: &mut ChaCha8Rng, n: usize) -> usize {
    if n == 0 {
        return 0;
    }
    ((rng::unit(rng) * n as f64) as usize).min(n - 1)
}

/// Shuffles `items` in place (Fisher–Yates).
pub(crate) fn shuffle<T>(rng: &mut ChaCha8Rng, items: &mut [T]) {
    for i in (1..items.len()).rev() {
        let j = index(rng, i + 1);
        items.swap(i, j);
    }
}

/// Breadth-first search over `adjacency` from `from`: for every node its number of edges from
/// `from` and the node it was reached from (`None` for `from` and for unreached nodes).
pub(crate) fn bfs(adjacency: &[Vec<usize>], from: usize) -> (Vec<Option<usize>>, Vec<Option<usize>>) {
    let n = adjacency.len();
    let mut dist = vec![None; n];
    let mut parent = vec![None; n];
    if from >= n {
        return (dist, parent);
    }
    dist[from] = Some(0);
    let mut queue = std::collections::VecDeque::from([from]);
    while let Some(k) = queue.pop_front() {
        let d = dist[k].unwrap_or(0);
        for &m in &adjacency[k] {
            if m < n && dist[m].is_none() {
                dist[m] = Some(d + 1);
                parent[m] = Some(k);
                queue.push_back(m);
            }
        }
    }
    (dist, parent)
}

/// The reached node with the most edges from the search's origin (lowest index on ties).
pub(crate) fn farthest(dist: &[Option<usize>]) -> Option<usize> {
    let mut best: Option<(usize, usize)> = None;
    for (k, d) in dist.iter().enumerate() {
        if let Some(d) = *d
            && best.is_none_or(|(_, bd)| d > bd)
        {
            best = Some((k, d));
        }
    }
    best.map(|(k, _)| k)
}

/// Two nodes far apart in `adjacency`, found by a double sweep from `first`: the farthest node
/// `a` from `first`, then the farthest node `b` from `a` (their distance is at least half the
/// diameter of `first`'s component). Returns `(a, b, edges between them)`.
pub(crate) fn far_pair(adjacency: &[Vec<usize>], first: usize) -> (usize, usize, usize) {
    let (d0, _) = bfs(adjacency, first);
    let a = farthest(&d0).unwrap_or(first);
    let (da, _) = bfs(adjacency, a);
    let b = farthest(&da).unwrap_or(a);
    (a, b, da.get(b).copied().flatten().unwrap_or(0))
}

/// The nodes from the search's origin to `to`, both included, following `parent`.
pub(crate) fn path_to(parent: &[Option<usize>], to: usize) -> Vec<usize> {
    let mut path = vec![to];
    let mut k = to;
    while let Some(p) = parent.get(k).copied().flatten() {
        path.push(p);
        k = p;
        if path.len() > parent.len() {
            break;
        }
    }
    path.reverse();
    path
}

/// An axis-aligned box obstacle covering `[x0, x1] × [y0, y1]` metres (`None` when empty).
pub(crate) fn aabb_box(x0: f64, y0: f64, x1: f64, y1: f64) -> Option<Obstacle> {
    let shape = ObstacleShape::Box {
        center: DVec2::new((x0 + x1) * 0.5, (y0 + y1) * 0.5),
        width: x1 - x0,
        height: y1 - y0,
        yaw: 0.0,
    };
    Obstacle::build(shape, DEFAULT_Z.0, DEFAULT_Z.1).ok()
}

/// The parts of `[lo, hi]` left once the `gaps` (intervals, any order) are cut out, shortest
/// piece kept [`MIN_PIECE_M`] long.
pub(crate) fn solid_runs(lo: f64, hi: f64, gaps: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut gaps: Vec<(f64, f64)> = gaps.to_vec();
    gaps.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut runs = Vec::new();
    let mut from = lo;
    for (g0, g1) in gaps {
        if g0 - from >= MIN_PIECE_M {
            runs.push((from, g0.min(hi)));
        }
        from = from.max(g1);
    }
    if hi - from >= MIN_PIECE_M {
        runs.push((from, hi));
    }
    runs
}

/// Shortest wall piece [`solid_runs`] keeps, metres.
pub(crate) const MIN_PIECE_M: f64 = 1e-6;

/// Whether every task of `scenario` joins its start to its goal for the agent's disc inside
/// `[min, max]`, by the grid flood fill of [`connected`].
pub(crate) fn solvable(scenario: &Scenario, min: DVec2, max: DVec2) -> bool {
    let world = scenario.world();
    scenario.tasks.iter().all(|t| connected(&world, min, max, t.start.position, t.goal, scenario.agent_radius))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn index_and_shuffle_stay_in_range() {
        let mut r = rng::stream(1, 0, 9);
        assert_eq!(index(&mut r, 0), 0);
        assert!((0..1000).all(|_| index(&mut r, 7) < 7));
        let mut v: Vec<usize> = (0..20).collect();
        shuffle(&mut r, &mut v);
        let mut sorted = v.clone();
        sorted.sort();
        assert_eq!(sorted, (0..20).collect::<Vec<_>>());
        assert_ne!(v, sorted, "a shuffle of 20 items left them in order");
    }

    #[test]
    fn searches_on_a_path_graph() {
        // 0 - 1 - 2 - 3, and 4 alone.
        let adj = vec![vec![1], vec![0, 2], vec![1, 3], vec![2], vec![]];
        let (dist, parent) = bfs(&adj, 1);
        assert_eq!(dist, [Some(1), Some(0), Some(1), Some(2), None]);
        assert_eq!(path_to(&parent, 3), [1, 2, 3]);
        assert_eq!(farthest(&dist), Some(3));
        assert_eq!(far_pair(&adj, 1), (3, 0, 3));
        assert_eq!(far_pair(&adj, 4), (4, 4, 0));
        assert_eq!(bfs(&adj, 9).0, [None; 5]);
    }

    #[test]
    fn runs_between_gaps() {
        assert_eq!(solid_runs(0.0, 10.0, &[]), [(0.0, 10.0)]);
        assert_eq!(solid_runs(0.0, 10.0, &[(6.0, 7.0), (2.0, 3.0)]), [(0.0, 2.0), (3.0, 6.0), (7.0, 10.0)]);
        assert_eq!(solid_runs(0.0, 10.0, &[(0.0, 1.0), (9.0, 10.0)]), [(1.0, 9.0)]);
        assert_eq!(solid_runs(0.0, 10.0, &[(-1.0, 11.0)]), Vec::<(f64, f64)>::new());
    }
}
