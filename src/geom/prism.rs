//! Distances in three dimensions between the body's capsules and obstacle prisms (seed 002 §5:
//! the upper body is checked against the obstacles' vertical extent; DESIGN.md §5).
//!
//! An obstacle part is a vertical prism: a convex outline ([`Shape`], a polygon or a circle)
//! swept from `z_min` to `z_max`. A prism is the Cartesian product of a planar convex set and
//! an interval, so its signed distance is exact in closed form: with `u` the outline's signed
//! distance of the point's `(x, y)` and `v` the interval's signed distance of its `z`, the
//! distance is `√(max(u, 0)² + max(v, 0)²)` when either is positive, and `max(u, v)` (the
//! shallower way out, negative) inside.
//!
//! A capsule is a segment and a radius; its clearance is the segment's least signed distance
//! less the radius (negative: the capsule reaches that far in). For a polygon outline the
//! least signed distance is exact in closed form:
//! - Inside, the prism's signed distance is the largest of its faces' plane distances, each
//!   linear along the segment, so the segment's deepest point solves a one-dimensional linear
//!   programme: by Helly's theorem in one dimension the least maximum of the lines is the
//!   largest least maximum of any two of them, each found where the two cross.
//! - When that least maximum is positive the segment misses the prism, and the distance of two
//!   disjoint convex sets is reached at an end of the segment or against one of the prism's
//!   edges (a face's interior is reached only by a segment parallel to it, which then reaches
//!   the face's edge or ends over it), so it is the least of the ends' distances and the
//!   segment–segment distances to the edges.
//!
//! For a circle outline (and an outline of more than [`MAX_LINES`] − 2 edges) the signed
//! distance along the segment is still convex, with one minimum, and golden-section search over the segment's parameter narrows it to 4·10⁻⁹ of the
//! segment.

use glam::{DVec2, DVec3};

use super::{ConvexPolygon, Shape};

/// A vertical prism: `base` from `z_min` to `z_max` (metres, `z_min < z_max`).
#[derive(Debug, Clone, Copy)]
pub struct Prism<'a> {
    /// The outline.
    pub base: &'a Shape,
    /// Bottom, metres.
    pub z_min: f64,
    /// Top, metres.
    pub z_max: f64,
}

/// A capsule: every point within `radius` of the segment `a`–`b`, metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Capsule {
    /// One end of the axis.
    pub a: DVec3,
    /// The other end.
    pub b: DVec3,
    /// Radius, metres.
    pub radius: f64,
}

/// Golden-section steps (circle outlines): the bracket shrinks by 0.618 each, to about 4·10⁻⁹ of the segment
/// after 40 (nanometres on a bone).
const GOLDEN_STEPS: usize = 40;

impl Prism<'_> {
    /// Signed distance from `p` to the prism, metres: negative inside (the depth of the
    /// shallowest way out), the Euclidean distance outside.
    pub fn signed_distance(&self, p: DVec3) -> f64 {
        let u = self.base.signed_distance(DVec2::new(p.x, p.y));
        let v = (self.z_min - p.z).max(p.z - self.z_max);
        if u > 0.0 || v > 0.0 { u.max(0.0).hypot(v.max(0.0)) } else { u.max(v) }
    }

    /// Signed distance from the segment `a`–`b` to the prism, metres, and the parameter
    /// `t ∈ [0, 1]` of the segment's point where it is reached.
    pub fn segment_distance(&self, a: DVec3, b: DVec3) -> (f64, f64) {
        if a == b {
            return (self.signed_distance(a), 0.0);
        }
        match self.base {
            Shape::Polygon(poly) => self.polygon_segment_distance(poly, a, b),
            Shape::Circle { .. } => self.golden_segment_distance(a, b),
        }
    }

    /// [`Prism::segment_distance`] for a polygon outline, in closed form (module docs).
    fn polygon_segment_distance(&self, poly: &ConvexPolygon, a: DVec3, b: DVec3) -> (f64, f64) {
        // Each face's plane distance along the segment, `c + s·t`: the outline's edges (their
        // outward normals, the interior on their left), then the bottom and the top.
        let d = b - a;
        let mut lines = [(0.0f64, 0.0f64); MAX_LINES];
        let vertices = poly.vertices();
        let k = vertices.len() + 2;
        if k > MAX_LINES {
            return self.golden_segment_distance(a, b);
        }
        for (i, (p, q)) in poly.edges().enumerate() {
            let e = q - p;
            let n = DVec2::new(e.y, -e.x) / e.length();
            lines[i] = (n.dot(DVec2::new(a.x, a.y) - p), n.dot(DVec2::new(d.x, d.y)));
        }
        lines[k - 2] = (self.z_min - a.z, -d.z);
        lines[k - 1] = (a.z - self.z_max, d.z);
        let lines = &lines[..k];
        let (deepest, t) = least_maximum(lines);
        if deepest <= 0.0 {
            return (deepest, t);
        }
        // Apart: the ends, then every edge of the prism.
        let mut best = (self.signed_distance(a), 0.0);
        let db = self.signed_distance(b);
        if db < best.0 {
            best = (db, 1.0);
        }
        let (lo, hi) = (self.z_min, self.z_max);
        for (p, q) in poly.edges() {
            for (u, v) in [(p.extend(lo), q.extend(lo)), (p.extend(hi), q.extend(hi)), (p.extend(lo), p.extend(hi))] {
                let (dist, t) = segment_segment(a, b, u, v);
                if dist < best.0 {
                    best = (dist, t);
                }
            }
        }
        best
    }

    /// [`Prism::segment_distance`] by golden-section search (module docs).
    fn golden_segment_distance(&self, a: DVec3, b: DVec3) -> (f64, f64) {
        let f = |t: f64| self.signed_distance(a.lerp(b, t));
        if a == b {
            return (f(0.0), 0.0);
        }
        const INV_PHI: f64 = 0.618_033_988_749_894_8;
        let (mut lo, mut hi) = (0.0f64, 1.0f64);
        let mut x1 = hi - INV_PHI * (hi - lo);
        let mut x2 = lo + INV_PHI * (hi - lo);
        let (mut f1, mut f2) = (f(x1), f(x2));
        for _ in 0..GOLDEN_STEPS {
            if f1 <= f2 {
                hi = x2;
                x2 = x1;
                f2 = f1;
                x1 = hi - INV_PHI * (hi - lo);
                f1 = f(x1);
            } else {
                lo = x1;
                x1 = x2;
                f1 = f2;
                x2 = lo + INV_PHI * (hi - lo);
                f2 = f(x2);
            }
        }
        // The ends themselves, should the minimum sit there.
        [(f1, x1), (f2, x2), (f(0.0), 0.0), (f(1.0), 1.0)]
            .into_iter()
            .fold((f64::INFINITY, 0.0), |best, c| if c.0 < best.0 { c } else { best })
    }

    /// Clearance between `capsule` and the prism, metres: the segment's signed distance less
    /// the radius (negative when they overlap).
    pub fn capsule_clearance(&self, capsule: &Capsule) -> f64 {
        self.segment_distance(capsule.a, capsule.b).0 - capsule.radius
    }
}

/// The most faces an outline may have for the closed form (more: golden-section search).
const MAX_LINES: usize = 66;

/// The least over `t ∈ [0, 1]` of the largest of the lines `c + s·t`, and a `t` where it is
/// reached (Helly's theorem in one dimension: the largest such least over pairs of lines).
fn least_maximum(lines: &[(f64, f64)]) -> (f64, f64) {
    let at = |(c, s): (f64, f64), t: f64| c + s * t;
    let mut m = f64::NEG_INFINITY;
    for (i, &l) in lines.iter().enumerate() {
        // One line alone: its least over the interval.
        m = m.max(at(l, 0.0).min(at(l, 1.0)));
        for &r in &lines[..i] {
            // Two lines: where they cross if one rises and the other falls, else an end.
            let (up, down) = if l.1 > r.1 { (l, r) } else { (r, l) };
            let pair = |t: f64| at(up, t).max(at(down, t));
            let v = if up.1 > 0.0 && down.1 < 0.0 {
                let t = ((down.0 - up.0) / (up.1 - down.1)).clamp(0.0, 1.0);
                pair(t)
            } else {
                pair(0.0).min(pair(1.0))
            };
            m = m.max(v);
        }
    }
    // A parameter reaching it: the intersection of the lines' intervals at or below `m`.
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for &(c, s) in lines {
        if s > 0.0 {
            hi = hi.min((m - c) / s);
        } else if s < 0.0 {
            lo = lo.max((m - c) / s);
        }
    }
    let t = if lo <= hi { 0.5 * (lo + hi) } else { lo.min(hi).clamp(0.0, 1.0) };
    (m, t.clamp(0.0, 1.0))
}

/// Distance between the segments `a`–`b` and `u`–`v` (the second may not be degenerate), and
/// the parameter on `a`–`b` of the closest point.
fn segment_segment(a: DVec3, b: DVec3, u: DVec3, v: DVec3) -> (f64, f64) {
    let (d1, d2, r) = (b - a, v - u, a - u);
    let (aa, ee, f) = (d1.length_squared(), d2.length_squared(), d2.dot(r));
    let (c, bb) = (d1.dot(r), d1.dot(d2));
    let denom = aa * ee - bb * bb;
    // The closest point of the lines, clamped to the first segment, then to the second.
    let mut s = if denom > 0.0 { ((bb * f - c * ee) / denom).clamp(0.0, 1.0) } else { 0.0 };
    let mut t = (bb * s + f) / ee;
    if t < 0.0 {
        t = 0.0;
        s = (-c / aa).clamp(0.0, 1.0);
    } else if t > 1.0 {
        t = 1.0;
        s = ((bb - c) / aa).clamp(0.0, 1.0);
    }
    ((a + d1 * s).distance(u + d2 * t), s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_to_a_box_prism_by_hand() {
        let base = Shape::Polygon(super::super::ConvexPolygon::from_box(DVec2::ZERO, 2.0, 2.0, 0.0).unwrap());
        let p = Prism { base: &base, z_min: 1.0, z_max: 2.0 };
        assert!((p.signed_distance(DVec3::new(0.0, 0.0, 1.5)) + 0.5).abs() < 1e-12);
        assert!((p.signed_distance(DVec3::new(0.0, 0.9, 1.5)) + 0.1).abs() < 1e-12);
        assert!((p.signed_distance(DVec3::new(0.0, 0.0, 0.4)) - 0.6).abs() < 1e-12);
        assert!((p.signed_distance(DVec3::new(4.0, 0.0, 6.0)) - 5.0).abs() < 1e-12);
        // A bar under the prism, across it: 0.3 below.
        let (d, t) = p.segment_distance(DVec3::new(-3.0, 0.2, 0.7), DVec3::new(3.0, 0.2, 0.7));
        assert!((d - 0.3).abs() < 1e-12, "{d}");
        assert!((0.0..=1.0).contains(&t));
        // A segment through it: the depth of its deepest point.
        let (d, t) = p.segment_distance(DVec3::new(-3.0, 0.0, 1.5), DVec3::new(3.0, 0.0, 1.5));
        assert!((d + 0.5).abs() < 1e-9 && (t - 0.5).abs() < 0.2, "{d} at {t}");
        let c = Capsule { a: DVec3::new(-3.0, 0.2, 0.7), b: DVec3::new(3.0, 0.2, 0.7), radius: 0.1 };
        assert!((p.capsule_clearance(&c) - 0.2).abs() < 1e-12);
    }

    #[test]
    fn distances_to_a_cylinder() {
        let base = Shape::circle(DVec2::new(1.0, 1.0), 0.5).unwrap();
        let p = Prism { base: &base, z_min: 0.0, z_max: 1.0 };
        assert!((p.signed_distance(DVec3::new(1.0, 2.5, 0.5)) - 1.0).abs() < 1e-12);
        assert!((p.signed_distance(DVec3::new(1.0, 2.5, 4.0)) - 1.0f64.hypot(3.0)).abs() < 1e-12);
        let (d, _) = p.segment_distance(DVec3::new(-5.0, 2.5, 0.5), DVec3::new(5.0, 2.5, 0.5));
        assert!((d - 1.0).abs() < 1e-12);
    }

    proptest::proptest! {
        /// The closed form agrees with golden-section search over the segment (which can only
        /// overestimate the least), and the point it names is that far from the prism.
        #[test]
        fn the_closed_form_is_the_searched_least(
            points in proptest::collection::vec((-1.0f64..1.0, -1.0f64..1.0), 3..9),
            z in (0.0f64..2.0, 0.05f64..1.0),
            ends in proptest::array::uniform6(-2.0f64..3.0),
        ) {
            let pts: Vec<DVec2> = points.iter().map(|&(x, y)| DVec2::new(x, y)).collect();
            let Ok(poly) = ConvexPolygon::hull(&pts) else { return Ok(()) };
            let base = Shape::Polygon(poly);
            let prism = Prism { base: &base, z_min: z.0, z_max: z.0 + z.1 };
            let a = DVec3::new(ends[0], ends[1], ends[2]);
            let b = DVec3::new(ends[3], ends[4], ends[5]);
            let (d, t) = prism.segment_distance(a, b);
            let (g, _) = prism.golden_segment_distance(a, b);
            proptest::prop_assert!(d <= g + 1e-12 && g - d < 1e-7, "closed {d}, searched {g}");
            let at = prism.signed_distance(a.lerp(b, t));
            proptest::prop_assert!((at - d).abs() < 1e-9, "{at} at {t} against {d}");
        }
    }
}
