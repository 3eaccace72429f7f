//! The visibility graph over the vertices of the polygonal approximations of the grown
//! obstacles, restricted to bitangent edges.
//!
//! Nodes are the vertices of every approximation polygon that do not lie in the interior of
//! another grown obstacle (all vertices of a convex polygon are convex). Two nodes are joined
//! when the segment between them is clear ([`Clearance::segment_clear`], exact rounded shapes)
//! and the segment's line supports both vertices' polygons, that is, it does not cut into the
//! polygon at either end. A shortest path among polygons only bends at vertices it wraps
//! around, so every edge of it has this property; dropping the other edges leaves the shortest
//! path unchanged and removes most candidate pairs. Two vertices of one polygon are joined only
//! when they are neighbours (any other chord crosses the polygon).

use std::f64::consts::{PI, TAU};

use glam::DVec2;

use super::clearance::{Blocker, Clearance};
use crate::geom::ConvexPolygon;

/// Angular slack (radians) of the coarse wedge filter; it only ever admits extra candidates.
const WEDGE_SLACK: f64 = 1e-6;

/// Relative tolerance of the supporting-line test; it only ever admits extra candidates.
const TANGENT_SLACK: f64 = 1e-12;

/// The polygon approximating one grown obstacle.
#[derive(Debug, Clone)]
pub(crate) struct Hull {
    /// Counter-clockwise vertices, metres.
    pub(crate) vertices: Vec<DVec2>,
    /// Node index of each vertex (`None`: inside another grown obstacle).
    pub(crate) nodes: Vec<Option<usize>>,
    /// Centre and radius of a disc containing the polygon, metres.
    center: DVec2,
    bound: f64,
}

impl Hull {
    /// Whether `p` lies in the closed polygon.
    pub(crate) fn contains(&self, p: DVec2) -> bool {
        let n = self.vertices.len();
        (0..n).all(|k| {
            let (a, b) = (self.vertices[k], self.vertices[(k + 1) % n]);
            (b - a).perp_dot(p - a) >= 0.0
        })
    }
}

/// A graph node: one polygon vertex with its neighbours on the polygon.
#[derive(Debug, Clone)]
pub(crate) struct Node {
    /// Position, metres.
    pub(crate) pos: DVec2,
    prev: DVec2,
    next: DVec2,
    /// Direction of the incoming polygon edge, radians.
    heading_in: f64,
    /// Exterior angle at the vertex, radians in `[0, π)`.
    turn: f64,
    /// Squared length of the longer adjacent polygon edge, square metres.
    reach2: f64,
}

impl Node {
    /// Whether the line through this vertex and `q` supports the vertex's polygon.
    pub(crate) fn supports(&self, q: DVec2) -> bool {
        let d = q - self.pos;
        let s1 = d.perp_dot(self.prev - self.pos);
        let s2 = d.perp_dot(self.next - self.pos);
        if s1 * s2 >= 0.0 {
            return true;
        }
        // Opposite sides: still accept when either neighbour is within rounding of the line.
        let tol2 = TANGENT_SLACK * TANGENT_SLACK * d.length_squared() * self.reach2;
        s1 * s1 <= tol2 || s2 * s2 <= tol2
    }

    /// Whether some direction from this vertex into the disc (`center`, `radius`) could give a
    /// supporting line (coarse filter, errs on the side of `true`).
    fn may_support_towards(&self, center: DVec2, radius: f64) -> bool {
        let to = center - self.pos;
        let dist = to.length();
        if !(dist > radius) {
            return true;
        }
        let half = (radius / dist).asin();
        // Supporting directions are those within `turn` after `heading_in`, modulo a half turn.
        let width = 2.0 * half + WEDGE_SLACK;
        if width >= PI - self.turn {
            return true;
        }
        let x = (to.y.atan2(to.x) - half - self.heading_in).rem_euclid(PI);
        x <= self.turn + WEDGE_SLACK || x + width >= PI
    }
}

/// Vertices of a polygon containing `blocker` grown by `radius`, with circular arcs replaced by
/// circumscribed segments, at most `TAU / arc_segments` radians each.
fn approximation(blocker: &Blocker, radius: f64, arc_segments: usize) -> Option<Vec<DVec2>> {
    match blocker {
        Blocker::Polygon { vertices, .. } => {
            let poly = ConvexPolygon::new(vertices).ok()?;
            Some(poly.grown(radius, arc_segments).ok()?.vertices().to_vec())
        }
        Blocker::Disc { center, radius: total } => {
            let n = arc_segments.max(4);
            let scale = center.x.abs().max(center.y.abs()) + total;
            let reach = total / (PI / n as f64).cos() + 8.0 * f64::EPSILON * scale;
            Some((0..n).map(|i| *center + DVec2::from_angle(TAU * i as f64 / n as f64) * reach).collect())
        }
    }
}

/// Approximation polygons and their nodes; edges are found when a search asks for them.
#[derive(Debug, Clone)]
pub(crate) struct Graph {
    pub(crate) hulls: Vec<Hull>,
    pub(crate) nodes: Vec<Node>,
    /// Hull of each node.
    hull_of: Vec<usize>,
    /// Conservative stand-in of each grown obstacle for occlusion (`None`: none).
    occluders: Vec<Option<Occluder>>,
    /// How far any approximation vertex lies outside its obstacle's indexed box, metres.
    stick_out: f64,
}

/// A convex shape strictly inside a grown obstacle's interior (as the clearance test counts
/// it): a segment that crosses it is blocked.
#[derive(Debug, Clone)]
enum Occluder {
    /// Counter-clockwise vertices.
    Polygon(Vec<DVec2>),
    /// Centre and radius.
    Disc(DVec2, f64),
}

impl Occluder {
    /// The occluder of `blocker` for agent radius `r` and tolerance `eps`.
    fn of(blocker: &Blocker, r: f64, eps: f64) -> Option<Occluder> {
        match blocker {
            Blocker::Disc { center, radius } => {
                let inner = radius - 2.0 * eps - 1e-9 * radius;
                (inner > 0.0).then_some(Occluder::Disc(*center, inner))
            }
            Blocker::Polygon { vertices, normals } => {
                // Every point within `r - eps` of the polygon is blocked; offset the edges by
                // at most half of that, so that even the offset corners stay well inside.
                let room = 0.5 * (r - eps);
                if !(room > 0.0) {
                    return None;
                }
                let n = vertices.len();
                let half_cos = |k: usize| (0.5 * (1.0 + normals[(k + n - 1) % n].dot(normals[k]))).max(0.0).sqrt();
                let delta = room * (0..n).map(half_cos).fold(1.0, f64::min);
                let offset = (0..n)
                    .map(|k| {
                        let (a, b) = (normals[(k + n - 1) % n], normals[k]);
                        let c = 1.0 + a.dot(b);
                        if c > 1e-9 { vertices[k] + (a + b) * (delta / c) } else { vertices[k] }
                    })
                    .collect();
                Some(Occluder::Polygon(offset))
            }
        }
    }

    /// The open range of directions `(lo, hi)` (radians, `lo < hi`, within 2π of each other)
    /// in which a ray from `p` crosses the occluder's interior, and the distance beyond which
    /// every point of such a ray lies behind it; `None` when `p` is not clearly outside.
    fn shadow(&self, p: DVec2) -> Option<(f64, f64, f64)> {
        const SLACK: f64 = 1e-9;
        match self {
            Occluder::Disc(center, radius) => {
                let to = *center - p;
                let d = to.length();
                if !(d > radius * (1.0 + 1e-9)) {
                    return None;
                }
                let half = (radius / d).asin() - SLACK;
                let mid = to.y.atan2(to.x);
                (half > 0.0).then_some((mid - half, mid + half, d + radius))
            }
            Occluder::Polygon(vertices) => {
                let n = vertices.len();
                // Clearly outside: beyond some edge's line.
                let outside = (0..n).any(|k| {
                    let (a, b) = (vertices[k], vertices[(k + 1) % n]);
                    (b - a).perp_dot(p - a) < -1e-9 * (b - a).length()
                });
                if !outside {
                    return None;
                }
                let first = vertices[0] - p;
                let base = first.y.atan2(first.x);
                let (mut lo, mut hi, mut far) = (0.0f64, 0.0f64, 0.0f64);
                for &v in vertices {
                    let to = v - p;
                    let rel = (to.y.atan2(to.x) - base + PI).rem_euclid(TAU) - PI;
                    lo = lo.min(rel);
                    hi = hi.max(rel);
                    far = far.max(to.length());
                }
                let (lo, hi) = (base + lo + SLACK, base + hi - SLACK);
                (lo < hi && hi - lo < PI).then_some((lo, hi, far))
            }
        }
    }
}

/// The directions from one point known to be blocked beyond some distance: a union of open
/// angular intervals, kept sorted and disjoint, over angles in `[-π, π]` (an interval across
/// the seam is split, each piece running past it so the seam itself counts as covered).
#[derive(Debug, Default)]
struct Shade {
    intervals: Vec<(f64, f64)>,
}

impl Shade {
    fn add(&mut self, lo: f64, hi: f64) {
        // Bring `lo` into [-π, π).
        let shift = ((lo + PI) / TAU).floor() * TAU;
        let (lo, hi) = (lo - shift, hi - shift);
        if hi > PI {
            self.insert(lo, PI + 1.0);
            self.insert(-PI - 1.0, hi - TAU);
        } else {
            self.insert(lo, hi);
        }
    }

    fn insert(&mut self, mut lo: f64, mut hi: f64) {
        // Merge with every interval it overlaps (open intervals merge only when they overlap).
        let at = self.intervals.partition_point(|&(_, h)| h <= lo);
        let mut end = at;
        while end < self.intervals.len() && self.intervals[end].0 < hi {
            lo = lo.min(self.intervals[end].0);
            hi = hi.max(self.intervals[end].1);
            end += 1;
        }
        self.intervals.splice(at..end, [(lo, hi)]);
    }

    /// Whether the direction `theta` (radians in `[-π, π]`) is inside the shade.
    fn covers(&self, theta: f64) -> bool {
        let at = self.intervals.partition_point(|&(_, h)| h <= theta);
        self.intervals.get(at).is_some_and(|&(lo, _)| lo < theta)
    }

    /// Whether every direction of the closed range `[lo, hi]` (radians, `hi - lo < π`) is
    /// inside the shade.
    fn covers_range(&self, lo: f64, hi: f64) -> bool {
        let shift = ((lo + PI) / TAU).floor() * TAU;
        let (lo, hi) = (lo - shift, hi - shift);
        let inside = |lo: f64, hi: f64| {
            let at = self.intervals.partition_point(|&(_, h)| h <= lo);
            self.intervals.get(at).is_some_and(|&(l, h)| l < lo && hi < h)
        };
        if hi > PI { inside(lo, PI) && inside(-PI, hi - TAU) } else { inside(lo, hi) }
    }

    /// Whether every direction is shaded.
    fn full(&self) -> bool {
        matches!(self.intervals.as_slice(), [(lo, hi)] if *lo < -PI && *hi > PI)
    }
}

/// An occluder waiting until the search radius passes its far distance.
#[derive(Debug, Clone, Copy)]
struct Pending {
    far: f64,
    lo: f64,
    hi: f64,
}

impl Graph {
    /// Builds the nodes; `None` when an approximation polygon cannot be built (coordinates out
    /// of the supported range).
    pub(crate) fn build(clearance: &Clearance, radius: f64, arc_segments: usize) -> Option<Graph> {
        let mut scratch = Vec::new();
        let mut hulls = Vec::new();
        let mut nodes = Vec::new();
        let mut hull_of = Vec::new();
        let mut stick_out = 0.0f64;
        for (h, blocker) in clearance.blockers().iter().enumerate() {
            let vertices = approximation(blocker, radius, arc_segments)?;
            let n = vertices.len();
            let mut ids = vec![None; n];
            for k in 0..n {
                let pos = vertices[k];
                if !clearance.point_free(pos, Some(h), &mut scratch) {
                    continue;
                }
                let prev = vertices[(k + n - 1) % n];
                let next = vertices[(k + 1) % n];
                let (e_in, e_out) = (pos - prev, next - pos);
                let turn = e_in.perp_dot(e_out).atan2(e_in.dot(e_out)).clamp(0.0, PI);
                ids[k] = Some(nodes.len());
                hull_of.push(h);
                let reach2 = e_in.length_squared().max(e_out.length_squared());
                nodes.push(Node { pos, prev, next, heading_in: e_in.y.atan2(e_in.x), turn, reach2 });
            }
            let aabb = clearance.grown_aabb(h);
            if let Some(b) = aabb {
                stick_out = vertices.iter().map(|&v| b.distance(v)).fold(stick_out, f64::max);
            }
            let center = aabb.map_or(vertices[0], |b| b.center());
            let bound = vertices.iter().map(|v| v.distance(center)).fold(0.0, f64::max) * (1.0 + 1e-9);
            hulls.push(Hull { vertices, nodes: ids, center, bound });
        }
        let (r, eps) = clearance.radius_and_tolerance();
        let occluders = clearance.blockers().iter().map(|b| Occluder::of(b, r, eps)).collect();
        // Rounding slack on top of the measured amount.
        let stick_out = stick_out * (1.0 + 1e-6) + 1e-9;
        Some(Graph { hulls, nodes, hull_of, occluders, stick_out })
    }

    /// Calls `visit(node)` for every node that might be seen from `p` and passes
    /// `admit(node)`: nodes behind a nearer obstacle are left out (with `cull`; without it,
    /// every node is visited). Hulls come nearest first; `wanted(index, hull)` may reject a
    /// hull before its nodes are looked at, and `admit`, a cheap test, rejects a node before
    /// the shade is.
    fn candidates(
        &self,
        clearance: &Clearance,
        p: DVec2,
        cull: bool,
        mut wanted: impl FnMut(usize, &Hull) -> bool,
        admit: impl Fn(usize) -> bool,
        mut visit: impl FnMut(usize),
    ) {
        let mut shade = Shade::default();
        let mut pending: Vec<Pending> = Vec::new();
        clearance.visit_nearest(p, |h, box_dist| {
            if cull {
                // Every node of this and later hulls lies at least this far from `p`.
                let reach = box_dist - self.stick_out;
                let mut k = 0;
                while k < pending.len() {
                    if pending[k].far < reach {
                        let q = pending.swap_remove(k);
                        shade.add(q.lo, q.hi);
                    } else {
                        k += 1;
                    }
                }
                if shade.full() {
                    return false;
                }
                if let Some((lo, hi, far)) = self.occluders[h].as_ref().and_then(|o| o.shadow(p)) {
                    pending.push(Pending { far, lo, hi });
                }
            }
            let hull = &self.hulls[h];
            if !wanted(h, hull) {
                return true;
            }
            if cull && let Some(b) = clearance.grown_aabb(h) {
                // The whole polygon lies in its box grown by the stick-out; skip it at once
                // when that box is in the shade.
                let b = b.expanded(self.stick_out);
                if !b.contains_point(p) {
                    let corners = [b.min, DVec2::new(b.max.x, b.min.y), b.max, DVec2::new(b.min.x, b.max.y)];
                    let first = corners[0] - p;
                    let base = first.y.atan2(first.x);
                    let (mut lo, mut hi) = (0.0f64, 0.0f64);
                    for c in corners {
                        let to = c - p;
                        let rel = (to.y.atan2(to.x) - base + PI).rem_euclid(TAU) - PI;
                        lo = lo.min(rel);
                        hi = hi.max(rel);
                    }
                    if hi - lo < PI && shade.covers_range(base + lo, base + hi) {
                        return true;
                    }
                }
            }
            for &v in hull.nodes.iter().flatten() {
                if !admit(v) {
                    continue;
                }
                let to = self.nodes[v].pos - p;
                if !cull || !shade.covers(to.y.atan2(to.x)) {
                    visit(v);
                }
            }
            true
        });
    }

    /// The neighbours of node `u` with edge lengths in metres: the next vertices along its own
    /// polygon and the vertices of other polygons joined by a clear bitangent segment.
    pub(crate) fn neighbours(&self, clearance: &Clearance, u: usize, cull: bool, out: &mut Vec<(usize, f64)>) {
        out.clear();
        let node = &self.nodes[u];
        let pu = node.pos;
        let h = self.hull_of[u];
        let hull = &self.hulls[h];
        let n = hull.vertices.len();
        if let Some(k) = hull.nodes.iter().position(|&x| x == Some(u)) {
            for w in [(k + 1) % n, (k + n - 1) % n] {
                if let Some(v) = hull.nodes[w]
                    && v != u
                    && clearance.segment_clear(pu, self.nodes[v].pos)
                {
                    out.push((v, pu.distance(self.nodes[v].pos)));
                }
            }
        }
        self.candidates(
            clearance,
            pu,
            cull,
            |k, other| k != h && node.may_support_towards(other.center, other.bound),
            |v| node.supports(self.nodes[v].pos) && self.nodes[v].supports(pu),
            |v| {
                let pv = self.nodes[v].pos;
                if clearance.segment_clear(pu, pv) {
                    out.push((v, pu.distance(pv)));
                }
            },
        );
        out.sort_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)));
        out.dedup_by_key(|x| x.0);
    }

    /// Whether node `u` joins the free point `p` by a clear segment along a line supporting
    /// the node's polygon (any vertex of a polygon whose approximation contains `p`).
    pub(crate) fn joins(&self, clearance: &Clearance, u: usize, p: DVec2) -> bool {
        self.may_join(u, p) && clearance.segment_clear(p, self.nodes[u].pos)
    }

    /// The cheap half of [`joins`](Self::joins): the line supports the node's polygon, or the
    /// polygon contains `p`.
    fn may_join(&self, u: usize, p: DVec2) -> bool {
        self.nodes[u].supports(p) || self.hulls[self.hull_of[u]].contains(p)
    }

    /// Nodes that a free point `p` can see along a line supporting the node's polygon (any
    /// vertex of a polygon whose approximation contains `p`), with distances in metres,
    /// ascending by node.
    pub(crate) fn endpoint_edges(&self, clearance: &Clearance, p: DVec2, cull: bool) -> Vec<(usize, f64)> {
        let mut out = Vec::new();
        self.candidates(
            clearance,
            p,
            cull,
            |_, _| true,
            |v| self.may_join(v, p),
            |v| {
                if clearance.segment_clear(p, self.nodes[v].pos) {
                    out.push((v, p.distance(self.nodes[v].pos)));
                }
            },
        );
        out.sort_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)));
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn node_at_corner() -> Node {
        // Corner of a counter-clockwise square at (1, 1): incoming edge heads +y, outgoing -x.
        let pos = DVec2::new(1.0, 1.0);
        let prev = DVec2::new(1.0, 0.0);
        let next = DVec2::new(0.0, 1.0);
        Node { pos, prev, next, heading_in: PI / 2.0, turn: PI / 2.0, reach2: 1.0 }
    }

    #[test]
    fn supporting_lines() {
        let n = node_at_corner();
        // The diagonal through the corner cuts the square.
        assert!(!n.supports(DVec2::new(3.0, 3.0)));
        assert!(!n.supports(DVec2::new(-3.0, -3.0)));
        assert!(n.supports(DVec2::new(3.0, -1.0)));
        assert!(n.supports(DVec2::new(1.0, 5.0)));
        assert!(!n.supports(DVec2::new(0.0, 0.5)));
        assert!(n.supports(DVec2::new(-1.0, 3.0)));
    }

    #[test]
    fn wedge_filter_agrees_with_support() {
        let n = node_at_corner();
        for i in 0..72 {
            let dir = DVec2::from_angle(TAU * i as f64 / 72.0);
            let far = n.pos + dir * 10.0;
            if n.supports(far) {
                assert!(n.may_support_towards(far, 0.01), "{i}");
            }
        }
        assert!(!n.may_support_towards(DVec2::new(-10.0, -9.0), 0.5));
        assert!(n.may_support_towards(DVec2::new(1.2, 1.2), 0.5));
    }
}
