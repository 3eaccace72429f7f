//! Exact clearance tests against obstacles grown by the agent radius.
//!
//! A world part grown by the radius `r` is the set of points within `r` of the part (a rounded
//! polygon, or a larger disc). These tests never approximate the rounded corners: a point or a
//! segment is blocked when it comes closer than `r - eps` to the original part, or, for a
//! polygon and `r <= eps`, when it reaches more than `eps` into the part. Touching the grown
//! boundary and sliding along it therefore count as free.

use glam::DVec2;

use super::rim::{Circle, angle_of, crossings};
use crate::geom::{Aabb, Shape, SpatialIndex};
use crate::world::World;

/// One world part as an obstacle for a disc-shaped agent.
#[derive(Debug, Clone)]
pub(crate) enum Blocker {
    /// A convex polygon: counter-clockwise vertices and the unit outward normal of each edge
    /// (edge `k` runs from vertex `k` to vertex `k + 1`).
    Polygon { vertices: Vec<DVec2>, normals: Vec<DVec2> },
    /// A disc already grown by the agent radius: centre and total radius, metres.
    Disc { center: DVec2, radius: f64 },
}

impl Blocker {
    /// The blocker for `shape` and agent radius `r`; `None` for a shape without interior.
    fn new(shape: &Shape, r: f64) -> Option<Blocker> {
        match shape {
            Shape::Polygon(poly) => {
                let vertices = poly.vertices().to_vec();
                let n = vertices.len();
                let normals: Vec<DVec2> = (0..n)
                    .map(|k| {
                        let e = vertices[(k + 1) % n] - vertices[k];
                        DVec2::new(e.y, -e.x).normalize_or_zero()
                    })
                    .collect();
                (n >= 3).then_some(Blocker::Polygon { vertices, normals })
            }
            Shape::Circle { center, radius } => {
                let total = radius + r;
                (total > 0.0 && total.is_finite()).then_some(Blocker::Disc { center: *center, radius: total })
            }
        }
    }

    /// Whether the point `p` lies in the interior of the grown shape (beyond the tolerance).
    fn blocks_point(&self, p: DVec2, r: f64, eps: f64) -> bool {
        match self {
            Blocker::Disc { center, radius } => p.distance(*center) < radius - eps,
            Blocker::Polygon { vertices, normals } => {
                let limit = r - eps;
                // For a convex polygon the largest edge-line offset is a lower bound on the
                // distance outside and equals minus the depth inside.
                let gap = vertices.iter().zip(normals).map(|(&v, &n)| n.dot(p - v)).fold(f64::NEG_INFINITY, f64::max);
                if gap >= limit {
                    return false;
                }
                if gap <= 0.0 {
                    return true;
                }
                let n = vertices.len();
                let dist = (0..n)
                    .map(|k| point_segment_distance(p, vertices[k], vertices[(k + 1) % n]))
                    .fold(f64::INFINITY, f64::min);
                dist < limit
            }
        }
    }

    /// Whether the segment `a`–`b` enters the interior of the grown shape (beyond the
    /// tolerance).
    fn blocks_segment(&self, a: DVec2, b: DVec2, r: f64, eps: f64) -> bool {
        match self {
            Blocker::Disc { center, radius } => point_segment_distance(*center, a, b) < radius - eps,
            Blocker::Polygon { vertices, normals } => {
                let limit = r - eps;
                // Separating-axis test over the polygon's edge normals and the segment's normal:
                // the largest gap is positive exactly when the two are disjoint, never exceeds
                // their distance, and is minus a penetration depth when they overlap.
                let mut gap = f64::NEG_INFINITY;
                for (&v, &n) in vertices.iter().zip(normals) {
                    gap = gap.max(n.dot(a - v).min(n.dot(b - v)));
                }
                let d = b - a;
                let len = d.length();
                if len > 0.0 {
                    let m = DVec2::new(-d.y, d.x) / len;
                    let s = m.dot(a);
                    let (lo, hi) = vertices
                        .iter()
                        .map(|&v| m.dot(v))
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| (lo.min(x), hi.max(x)));
                    gap = gap.max(lo - s).max(s - hi);
                }
                if gap >= limit {
                    return false;
                }
                if gap <= 0.0 {
                    return true;
                }
                let n = vertices.len();
                let mut dist = f64::INFINITY;
                for k in 0..n {
                    let (v, w) = (vertices[k], vertices[(k + 1) % n]);
                    dist = dist
                        .min(point_segment_distance(v, a, b))
                        .min(point_segment_distance(a, v, w))
                        .min(point_segment_distance(b, v, w));
                }
                dist < limit
            }
        }
    }
}

/// Distance in metres from `p` to the segment `a`–`b`.
pub(crate) fn point_segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 { ((p - a).dot(ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
    p.distance(a + ab * t)
}

/// The world's parts grown by the agent radius, with a spatial index over the grown boxes.
#[derive(Debug, Clone)]
pub(crate) struct Clearance {
    blockers: Vec<Blocker>,
    /// Index into `blockers`.
    index: SpatialIndex,
    radius: f64,
    eps: f64,
}

impl Clearance {
    /// Grows every part of `world` by `radius` metres; `eps` is the tolerance in metres.
    pub(crate) fn new(world: &World, radius: f64, eps: f64) -> Clearance {
        let mut blockers = Vec::new();
        let mut boxes = Vec::new();
        for part in world.parts() {
            if let Some(b) = Blocker::new(&part.shape, radius) {
                boxes.push(part.shape.aabb().expanded(radius + eps));
                blockers.push(b);
            }
        }
        Clearance { index: SpatialIndex::build(&boxes), blockers, radius, eps }
    }

    /// The grown obstacles.
    pub(crate) fn blockers(&self) -> &[Blocker] {
        &self.blockers
    }

    /// Box of blocker `i` grown by the radius, metres.
    pub(crate) fn grown_aabb(&self, i: usize) -> Option<Aabb> {
        self.index.aabb(i).copied()
    }

    /// Blocker `j`.
    pub(crate) fn blocker(&self, j: usize) -> &Blocker {
        &self.blockers[j]
    }

    /// Whether `p` lies in the interior of grown obstacle `j` (beyond the tolerance).
    pub(crate) fn blocks_point(&self, j: usize, p: DVec2) -> bool {
        self.blockers[j].blocks_point(p, self.radius, self.eps)
    }

    /// Replaces `out` with the grown obstacles whose boxes lie within `reach` metres of `p`.
    pub(crate) fn near(&self, p: DVec2, reach: f64, out: &mut Vec<usize>) {
        self.index.query_circle(p, reach, out);
    }

    /// Appends to `out` the directions (radians from `rim`'s centre) in which the circle `rim`
    /// (radius > 0) may cross the boundary of grown obstacle `j`'s interior as the point tests
    /// count it: for a disc, where it meets the disc shrunk by the tolerance; for a polygon,
    /// where it meets the lines of the edges moved out by `r − ε` and, for `r > ε`, the
    /// circles of that radius round the corners. Every true crossing is among them.
    pub(crate) fn cuts(&self, j: usize, rim: Circle, out: &mut Vec<f64>) {
        let rho = rim.radius;
        let meet = |center: DVec2, radius: f64, out: &mut Vec<f64>| {
            let to = center - rim.center;
            let d = to.length();
            if d > 0.0 && radius > 0.0 {
                crossings(angle_of(to), (d * d + rho * rho - radius * radius) / (2.0 * rho * d), out);
            }
        };
        match &self.blockers[j] {
            Blocker::Disc { center, radius } => meet(*center, radius - self.eps, out),
            Blocker::Polygon { vertices, normals } => {
                let limit = self.radius - self.eps;
                for (&v, &n) in vertices.iter().zip(normals) {
                    crossings(angle_of(n), (limit - n.dot(rim.center - v)) / rho, out);
                }
                if limit > 0.0 {
                    vertices.iter().for_each(|&v| meet(v, limit, out));
                }
            }
        }
    }

    /// Whether `p` lies outside the interior of every grown obstacle other than `skip`.
    pub(crate) fn point_free(&self, p: DVec2, skip: Option<usize>, scratch: &mut Vec<usize>) -> bool {
        if !p.is_finite() {
            return false;
        }
        self.index.query_circle(p, 0.0, scratch);
        scratch.iter().filter(|&&i| Some(i) != skip).all(|&i| !self.blockers[i].blocks_point(p, self.radius, self.eps))
    }

    /// Whether the segment `a`–`b` stays outside the interior of every grown obstacle.
    pub(crate) fn segment_clear(&self, a: DVec2, b: DVec2) -> bool {
        if !(a.is_finite() && b.is_finite()) {
            return false;
        }
        !self.index.any_along(a, b - a, 1.0, |i| self.blockers[i].blocks_segment(a, b, self.radius, self.eps))
    }

    /// [`Clearance::segment_clear`] leaving out the grown obstacles `skip`: those the segment
    /// is known to touch only from outside (a tangent at its end).
    pub(crate) fn segment_clear_except(&self, a: DVec2, b: DVec2, skip: [usize; 2]) -> bool {
        if !(a.is_finite() && b.is_finite()) {
            return false;
        }
        !self.index.any_along(a, b - a, 1.0, |i| {
            !skip.contains(&i) && self.blockers[i].blocks_segment(a, b, self.radius, self.eps)
        })
    }

    /// Visits the grown obstacles nearest first by the distance of their boxes from `p`,
    /// passing over the parts of the index whose bounds `open` refuses
    /// ([`SpatialIndex::visit_nearest_within`]).
    pub(crate) fn visit_nearest(
        &self,
        p: DVec2,
        open: impl FnMut(&Aabb, f64) -> bool,
        visit: impl FnMut(usize, f64) -> bool,
    ) {
        self.index.visit_nearest_within(p, open, visit);
    }

    /// The agent radius and the tolerance, metres.
    pub(crate) fn radius_and_tolerance(&self) -> (f64, f64) {
        (self.radius, self.eps)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::ConvexPolygon;

    fn v(x: f64, y: f64) -> DVec2 {
        DVec2::new(x, y)
    }

    fn unit_box() -> Blocker {
        let sq = ConvexPolygon::from_box(DVec2::ZERO, 2.0, 2.0, 0.0).unwrap();
        Blocker::new(&Shape::Polygon(sq), 0.5).unwrap()
    }

    #[test]
    fn polygon_points() {
        let b = unit_box();
        let eps = 1e-9;
        assert!(b.blocks_point(v(0.0, 0.0), 0.5, eps));
        assert!(b.blocks_point(v(1.4, 0.0), 0.5, eps));
        assert!(!b.blocks_point(v(1.5, 0.0), 0.5, eps));
        // Near the rounded corner: inside the bounding square but outside the disc.
        let c = v(1.0, 1.0) + DVec2::splat(0.36);
        assert!(!b.blocks_point(c, 0.5, eps));
        assert!(b.blocks_point(v(1.0, 1.0) + DVec2::splat(0.35), 0.5, eps));
    }

    #[test]
    fn polygon_segments() {
        let b = unit_box();
        let eps = 1e-9;
        // Sliding along the grown top edge is free; one millimetre lower is not.
        assert!(!b.blocks_segment(v(-3.0, 1.5), v(3.0, 1.5), 0.5, eps));
        assert!(b.blocks_segment(v(-3.0, 1.499), v(3.0, 1.499), 0.5, eps));
        // Crossing the box without any vertex near the segment.
        assert!(b.blocks_segment(v(-3.0, 0.1), v(3.0, -0.1), 0.5, eps));
        // Passing the rounded corner diagonally: the segment x + y = 2 + 0.5·√2 touches it.
        let k = 2.0 + 0.5 * 2f64.sqrt();
        assert!(!b.blocks_segment(v(k - 3.0, 3.0), v(3.0, k - 3.0), 0.5, 1e-9));
        assert!(b.blocks_segment(v(k - 3.01, 3.0), v(3.0, k - 3.01), 0.5, 1e-9));
        // A point agent may run along an edge but not through the box.
        assert!(!b.blocks_segment(v(-1.0, 1.0), v(1.0, 1.0), 0.0, eps));
        assert!(b.blocks_segment(v(-1.0, 1.0), v(1.0, -1.0), 0.0, eps));
    }

    #[test]
    fn discs() {
        let d = Blocker::new(&Shape::circle(v(0.0, 0.0), 1.0).unwrap(), 0.5).unwrap();
        assert!(!d.blocks_segment(v(-3.0, 1.5), v(3.0, 1.5), 0.5, 1e-9));
        assert!(d.blocks_segment(v(-3.0, 1.49), v(3.0, 1.49), 0.5, 1e-9));
        assert!(d.blocks_point(v(1.0, 1.0), 0.5, 1e-9));
        assert!(!d.blocks_point(v(1.1, 1.1), 0.5, 1e-9));
        assert!(Blocker::new(&Shape::circle(v(0.0, 0.0), 0.0).unwrap(), 0.0).is_none());
    }

    #[test]
    fn distances() {
        assert_eq!(point_segment_distance(v(0.0, 1.0), v(-1.0, 0.0), v(1.0, 0.0)), 1.0);
        assert_eq!(point_segment_distance(v(3.0, 0.0), v(-1.0, 0.0), v(1.0, 0.0)), 2.0);
        assert_eq!(point_segment_distance(v(3.0, 4.0), v(0.0, 0.0), v(0.0, 0.0)), 5.0);
    }
}
