//! Static bounding-volume hierarchy over axis-aligned boxes.

use std::cmp::{Ordering, Reverse};
use std::collections::BinaryHeap;

use glam::DVec2;

use super::Aabb;

/// Items per leaf.
const LEAF_SIZE: usize = 4;

/// Traversal stack capacity. Median splits halve the item count at every level, so the tree is
/// at most `log2(len / LEAF_SIZE) + 2` levels deep and the stack never holds more entries than
/// that; 128 covers any `usize` item count.
const STACK: usize = 128;

/// Spatial index answering "which items are near this circle / along this ray segment".
///
/// It is a static bounding-volume hierarchy (BVH) built once from item boxes by recursive median
/// splits along the wider axis of the item centres. A BVH was chosen over a uniform grid because
/// obstacle sizes in one world vary widely (long walls next to small crates): a grid needs one
/// cell size, and large items then occupy many cells while small items crowd one cell, whereas
/// the BVH adapts to the data. Each item sits in exactly one leaf, so queries never produce
/// duplicates and need no "already seen" marks. A query visits `O(log n + k)` nodes for `k`
/// nearby items; building takes `O(n log n)`. Rebuild the index when items move.
///
/// Queries write matching item indices (positions in the slice given to [`SpatialIndex::build`])
/// into a caller-provided vector, sorted ascending; they do not allocate when the vector already
/// has enough capacity. The result is exactly the set a linear scan with the same predicate
/// ([`Aabb::distance`] or [`Aabb::intersects_segment`]) would return.
#[derive(Debug, Clone, Default)]
pub struct SpatialIndex {
    nodes: Vec<Node>,
    /// Item indices, grouped so that every leaf owns a contiguous range.
    order: Vec<usize>,
    /// Item boxes by original index.
    boxes: Vec<Aabb>,
}

/// A tree node: a leaf owning `order[first..first + count]`, or (with `count == 0`) an inner
/// node with children `first` and `second`.
#[derive(Debug, Clone, Copy)]
struct Node {
    bounds: Aabb,
    first: usize,
    second: usize,
    count: usize,
}

/// A pending entry of [`SpatialIndex::visit_nearest`].
#[derive(Debug, Clone, Copy)]
struct Near {
    dist: f64,
    item: bool,
    index: usize,
}

impl Ord for Near {
    fn cmp(&self, other: &Self) -> Ordering {
        // Items sort before nodes at the same distance, so that an item is reported before any
        // node whose box merely touches the same distance is opened.
        self.dist.total_cmp(&other.dist).then(other.item.cmp(&self.item)).then(self.index.cmp(&other.index))
    }
}

impl PartialOrd for Near {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for Near {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Near {}

impl SpatialIndex {
    /// Builds the index over `aabbs` (metres); item `i` is `aabbs[i]`. Boxes with NaN corners or
    /// `min > max` are kept but never reported.
    pub fn build(aabbs: &[Aabb]) -> Self {
        let mut index = SpatialIndex { nodes: Vec::new(), order: (0..aabbs.len()).collect(), boxes: aabbs.to_vec() };
        if !aabbs.is_empty() {
            let centers: Vec<DVec2> = aabbs.iter().map(Aabb::center).collect();
            index.build_node(&centers, 0, aabbs.len());
        }
        index
    }

    /// Appends the node for `order[start..end]` and returns its position.
    fn build_node(&mut self, centers: &[DVec2], start: usize, end: usize) -> usize {
        let items = &self.order[start..end];
        let bounds = items.iter().skip(1).fold(self.boxes[items[0]], |b, &i| b.union(&self.boxes[i]));
        let slot = self.nodes.len();
        self.nodes.push(Node { bounds, first: start, second: 0, count: end - start });
        if end - start <= LEAF_SIZE {
            return slot;
        }
        let (lo, hi) = items
            .iter()
            .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), &i| (lo.min(centers[i]), hi.max(centers[i])));
        let spread = hi - lo;
        let axis = usize::from(spread.y > spread.x);
        let mid = start + (end - start) / 2;
        self.order[start..end].select_nth_unstable_by(mid - start, |&a, &b| {
            centers[a][axis].total_cmp(&centers[b][axis]).then(a.cmp(&b))
        });
        let left = self.build_node(centers, start, mid);
        let right = self.build_node(centers, mid, end);
        self.nodes[slot] = Node { bounds, first: left, second: right, count: 0 };
        slot
    }

    /// Number of indexed items.
    pub fn len(&self) -> usize {
        self.boxes.len()
    }

    /// Whether the index holds no items.
    pub fn is_empty(&self) -> bool {
        self.boxes.is_empty()
    }

    /// Box of item `i` as given to [`SpatialIndex::build`].
    pub fn aabb(&self, i: usize) -> Option<&Aabb> {
        self.boxes.get(i)
    }

    /// Box around all items; `None` when empty.
    pub fn bounds(&self) -> Option<Aabb> {
        self.nodes.first().map(|n| n.bounds)
    }

    /// Replaces the contents of `out` with the indices of items whose box is within `radius`
    /// metres of `center` (`aabb.distance(center) <= radius`), ascending.
    pub fn query_circle(&self, center: DVec2, radius: f64, out: &mut Vec<usize>) {
        self.query(out, |b| b.distance(center) <= radius);
    }

    /// Replaces the contents of `out` with the indices of items whose box the segment
    /// `origin + t·dir`, `t ∈ [0, max_dist]`, touches ([`Aabb::intersects_segment`]), ascending.
    /// With a unit `dir`, `max_dist` is in metres.
    pub fn query_ray(&self, origin: DVec2, dir: DVec2, max_dist: f64, out: &mut Vec<usize>) {
        self.query(out, |b| b.intersects_segment(origin, dir, max_dist));
    }

    /// Replaces the contents of `out` with the indices of items whose box, grown by `radius`,
    /// the segment `a`–`b` touches (every item within `radius` of the segment is among them),
    /// ascending.
    pub fn query_capsule(&self, a: DVec2, b: DVec2, radius: f64, out: &mut Vec<usize>) {
        let d = b - a;
        let len = d.length();
        if !(len > 1e-12) {
            self.query_circle(a, radius, out);
            return;
        }
        let dir = d / len;
        self.query(out, |bx| bx.expanded(radius).intersects_segment(a, dir, len));
    }

    /// Whether `hit` holds for some item whose box the segment `origin + t·dir`,
    /// `t ∈ [0, max_dist]`, touches. Boxes are visited roughly front to back along the segment
    /// and the walk stops at the first item for which `hit` is true, so a segment blocked near
    /// its start costs little however long it is.
    pub fn any_along(&self, origin: DVec2, dir: DVec2, max_dist: f64, mut hit: impl FnMut(usize) -> bool) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let mut stack = [0usize; STACK];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = self.nodes[stack[top]];
            if !node.bounds.intersects_segment(origin, dir, max_dist) {
                continue;
            }
            if node.count > 0 {
                for &item in &self.order[node.first..node.first + node.count] {
                    if self.boxes[item].intersects_segment(origin, dir, max_dist) && hit(item) {
                        return true;
                    }
                }
            } else if top + 2 <= STACK {
                // The child nearer the origin along `dir` is popped first.
                let ahead = dir.dot(self.nodes[node.second].bounds.center() - self.nodes[node.first].bounds.center());
                let (near, far) = if ahead >= 0.0 { (node.first, node.second) } else { (node.second, node.first) };
                stack[top] = far;
                stack[top + 1] = near;
                top += 2;
            }
        }
        false
    }

    /// Visits items in ascending order of their box's distance from `p` (ties by index) until
    /// `visit(item, distance)` returns `false`. Boxes with NaN corners are never visited.
    pub fn visit_nearest(&self, p: DVec2, visit: impl FnMut(usize, f64) -> bool) {
        self.visit_nearest_within(p, |_, _| true, visit);
    }

    /// [`SpatialIndex::visit_nearest`], asking `open(bounds, distance)` before looking into each
    /// node of the tree (in the same order, at its box's distance from `p`): a node it refuses
    /// is passed over with every item in it.
    pub fn visit_nearest_within(
        &self,
        p: DVec2,
        mut open: impl FnMut(&Aabb, f64) -> bool,
        mut visit: impl FnMut(usize, f64) -> bool,
    ) {
        if self.nodes.is_empty() || p.is_nan() {
            return;
        }
        // Entries ordered by distance, then items before nodes, then index.
        let mut heap = BinaryHeap::new();
        heap.push(Reverse(Near { dist: self.nodes[0].bounds.distance(p), item: false, index: 0 }));
        while let Some(Reverse(Near { dist, item, index })) = heap.pop() {
            if item {
                if !visit(index, dist) {
                    return;
                }
                continue;
            }
            let node = self.nodes[index];
            if !open(&node.bounds, dist) {
                continue;
            }
            if node.count > 0 {
                for &i in &self.order[node.first..node.first + node.count] {
                    let d = self.boxes[i].distance(p);
                    if d.is_finite() {
                        heap.push(Reverse(Near { dist: d, item: true, index: i }));
                    }
                }
            } else {
                for child in [node.first, node.second] {
                    let d = self.nodes[child].bounds.distance(p);
                    if d.is_finite() {
                        heap.push(Reverse(Near { dist: d, item: false, index: child }));
                    }
                }
            }
        }
    }

    /// Depth-first traversal with a fixed stack; `hit` must be monotone (true for a box whenever
    /// it is true for a box inside it). Returns the number of nodes visited.
    fn query(&self, out: &mut Vec<usize>, hit: impl Fn(&Aabb) -> bool) -> usize {
        out.clear();
        if self.nodes.is_empty() {
            return 0;
        }
        let mut stack = [0usize; STACK];
        let mut top = 1;
        let mut visited = 0;
        while top > 0 {
            top -= 1;
            visited += 1;
            let node = self.nodes[stack[top]];
            if !hit(&node.bounds) {
                continue;
            }
            if node.count > 0 {
                for &item in &self.order[node.first..node.first + node.count] {
                    if hit(&self.boxes[item]) {
                        out.push(item);
                    }
                }
            } else if top + 2 <= STACK {
                stack[top] = node.second;
                stack[top + 1] = node.first;
                top += 2;
            }
        }
        out.sort_unstable();
        visited
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid_boxes(side: usize) -> Vec<Aabb> {
        let mut boxes = Vec::new();
        for y in 0..side {
            for x in 0..side {
                let c = DVec2::new(x as f64 * 2.0, y as f64 * 2.0);
                boxes.push(Aabb::around(c, 0.5));
            }
        }
        boxes
    }

    #[test]
    fn circle_query_on_grid() {
        let boxes = grid_boxes(10);
        let index = SpatialIndex::build(&boxes);
        assert_eq!(index.len(), 100);
        let mut out = Vec::new();
        // Around (2, 2): the box itself plus its four neighbours at distance 2 - 0.5 = 1.5; the
        // diagonal neighbours are at 1.5·√2.
        index.query_circle(DVec2::new(2.0, 2.0), 1.5, &mut out);
        assert_eq!(out, vec![1, 10, 11, 12, 21]);
        index.query_circle(DVec2::new(2.0, 2.0), 1.49, &mut out);
        assert_eq!(out, vec![11]);
        index.query_circle(DVec2::new(-50.0, 0.0), 1.0, &mut out);
        assert!(out.is_empty());
    }

    #[test]
    fn ray_query_on_grid() {
        let boxes = grid_boxes(10);
        let index = SpatialIndex::build(&boxes);
        let mut out = Vec::new();
        index.query_ray(DVec2::new(-1.0, 4.0), DVec2::X, 4.0, &mut out);
        assert_eq!(out, vec![20, 21]);
        index.query_ray(DVec2::new(-1.0, 4.0), -DVec2::X, 40.0, &mut out);
        assert!(out.is_empty());
    }

    #[test]
    fn queries_touch_only_nearby_nodes() {
        // 5,000 boxes of 0.2–1.2 m scattered over a 300 m square (fixed linear congruential
        // sequence), queried with a 3 m circle.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let boxes: Vec<Aabb> = (0..5000)
            .map(|_| {
                let c = DVec2::new(next() * 300.0, next() * 300.0);
                Aabb::around(c, 0.1 + next() * 0.5)
            })
            .collect();
        let index = SpatialIndex::build(&boxes);
        let mut out = Vec::with_capacity(64);
        let mut worst = 0;
        for k in 0..200 {
            let center = DVec2::new((k * 37 % 300) as f64, (k * 91 % 300) as f64);
            let visited = index.query(&mut out, |b| b.distance(center) <= 3.0);
            let brute = boxes.iter().filter(|b| b.distance(center) <= 3.0).count();
            assert_eq!(out.len(), brute);
            worst = worst.max(visited);
        }
        assert!(worst < 120, "visited {worst} nodes");
        let visited = index.query(&mut out, |b| b.intersects_segment(DVec2::new(150.0, 150.0), DVec2::X, 5.0));
        assert!(visited < 120, "visited {visited} nodes");
    }

    #[test]
    fn nearest_first_and_first_hit_agree_with_a_linear_scan() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let boxes: Vec<Aabb> =
            (0..400).map(|_| Aabb::around(DVec2::new(next() * 50.0, next() * 50.0), 0.1 + next())).collect();
        let index = SpatialIndex::build(&boxes);
        for _ in 0..50 {
            let p = DVec2::new(next() * 60.0 - 5.0, next() * 60.0 - 5.0);
            let mut seen = Vec::new();
            index.visit_nearest(p, |i, d| {
                seen.push((d, i));
                true
            });
            let mut expected: Vec<(f64, usize)> = boxes.iter().enumerate().map(|(i, b)| (b.distance(p), i)).collect();
            expected.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            assert_eq!(seen, expected);
            // Stopping early stops the walk.
            let mut count = 0;
            index.visit_nearest(p, |_, _| {
                count += 1;
                count < 5
            });
            assert_eq!(count, 5);
            // Nodes refused are passed over, with their items only.
            let mut kept = Vec::new();
            index.visit_nearest_within(
                p,
                |b, _| b.min.x <= 25.0,
                |i, d| {
                    kept.push((d, i));
                    true
                },
            );
            assert!(kept.windows(2).all(|w| w[0] <= w[1]));
            assert!(expected.iter().filter(|(_, i)| boxes[*i].min.x <= 25.0).all(|e| kept.contains(e)));
            assert!(kept.len() < expected.len());

            let dir = DVec2::from_angle(next() * std::f64::consts::TAU);
            let len = next() * 40.0;
            let along: Vec<usize> = (0..boxes.len()).filter(|&i| boxes[i].intersects_segment(p, dir, len)).collect();
            let target = along.get(along.len() / 2).copied();
            let mut tested = Vec::new();
            let found = index.any_along(p, dir, len, |i| {
                tested.push(i);
                Some(i) == target
            });
            assert_eq!(found, target.is_some());
            assert!(tested.iter().all(|i| along.contains(i)));
            assert!(!index.any_along(p, dir, len, |_| false));
        }
    }

    #[test]
    fn empty_and_degenerate() {
        let mut out = vec![7];
        SpatialIndex::build(&[]).query_circle(DVec2::ZERO, 10.0, &mut out);
        assert!(out.is_empty());
        let boxes = [
            Aabb::new(DVec2::splat(f64::NAN), DVec2::ONE),
            Aabb::new(DVec2::ONE, DVec2::ZERO),
            Aabb::around(DVec2::ZERO, 1.0),
        ];
        let index = SpatialIndex::build(&boxes);
        index.query_circle(DVec2::ZERO, 100.0, &mut out);
        assert_eq!(out, vec![2]);
        index.query_circle(DVec2::ZERO, f64::NAN, &mut out);
        assert!(out.is_empty());
    }
}
