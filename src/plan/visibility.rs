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

/// Approximation polygons, nodes and bitangent edges among the obstacles.
#[derive(Debug, Clone)]
pub(crate) struct Graph {
    pub(crate) hulls: Vec<Hull>,
    pub(crate) nodes: Vec<Node>,
    /// Neighbours of each node with the edge length in metres, ascending by neighbour.
    pub(crate) adjacency: Vec<Vec<(usize, f64)>>,
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

impl Graph {
    /// Builds the graph; `None` when an approximation polygon cannot be built (coordinates out
    /// of the supported range).
    pub(crate) fn build(clearance: &Clearance, radius: f64, arc_segments: usize) -> Option<Graph> {
        let mut scratch = Vec::new();
        let mut hulls = Vec::new();
        let mut nodes = Vec::new();
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
                let reach2 = e_in.length_squared().max(e_out.length_squared());
                nodes.push(Node { pos, prev, next, heading_in: e_in.y.atan2(e_in.x), turn, reach2 });
            }
            let center = clearance.grown_aabb(h).map_or(vertices[0], |b| b.center());
            let bound = vertices.iter().map(|v| v.distance(center)).fold(0.0, f64::max) * (1.0 + 1e-9);
            hulls.push(Hull { vertices, nodes: ids, center, bound });
        }

        let mut adjacency = vec![Vec::new(); nodes.len()];
        let add = |adjacency: &mut Vec<Vec<(usize, f64)>>, u: usize, v: usize, len: f64| {
            adjacency[u].push((v, len));
            adjacency[v].push((u, len));
        };
        for (a, hull) in hulls.iter().enumerate() {
            let n = hull.vertices.len();
            for k in 0..n {
                let Some(u) = hull.nodes[k] else { continue };
                let pu = nodes[u].pos;
                // Sliding along the polygon boundary.
                if let Some(v) = hull.nodes[(k + 1) % n]
                    && v != u
                    && clearance.segment_clear(pu, nodes[v].pos, &mut scratch)
                {
                    add(&mut adjacency, u, v, pu.distance(nodes[v].pos));
                }
                for other in &hulls[a + 1..] {
                    if !nodes[u].may_support_towards(other.center, other.bound) {
                        continue;
                    }
                    for &v in other.nodes.iter().flatten() {
                        let pv = nodes[v].pos;
                        if nodes[u].supports(pv)
                            && nodes[v].supports(pu)
                            && clearance.segment_clear(pu, pv, &mut scratch)
                        {
                            add(&mut adjacency, u, v, pu.distance(pv));
                        }
                    }
                }
            }
        }
        for list in &mut adjacency {
            list.sort_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)));
            list.dedup_by_key(|x| x.0);
        }
        Some(Graph { hulls, nodes, adjacency })
    }

    /// Nodes that a free point `p` can see along a line supporting the node's polygon (any
    /// vertex of a polygon whose approximation contains `p`), with distances in metres,
    /// ascending by node.
    pub(crate) fn endpoint_edges(
        &self,
        clearance: &Clearance,
        p: DVec2,
        scratch: &mut Vec<usize>,
    ) -> Vec<(usize, f64)> {
        let mut out = Vec::new();
        for hull in &self.hulls {
            let inside = hull.contains(p);
            for &v in hull.nodes.iter().flatten() {
                let pv = self.nodes[v].pos;
                if (inside || self.nodes[v].supports(p)) && clearance.segment_clear(p, pv, scratch) {
                    out.push((v, p.distance(pv)));
                }
            }
        }
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
