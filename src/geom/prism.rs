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
//! A capsule is a segment and a radius. The signed distance to a convex set is a convex
//! function, so along the segment it has one minimum; golden-section search over the segment's
//! parameter narrows it to a width of 10⁻¹⁵ of the segment, and the capsule's clearance is that
//! minimum less the radius (negative: the capsule reaches that far in).

use glam::{DVec2, DVec3};

use super::Shape;

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

/// Golden-section steps: the bracket shrinks by 0.618 each, to about 4·10⁻⁹ of the segment
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
}
