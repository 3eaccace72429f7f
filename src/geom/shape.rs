//! Obstacle shapes: convex polygons and circles.

use std::f64::consts::TAU;

use glam::DVec2;

use super::{Aabb, ConvexPolygon, GeomError, Obb, sanitize, unit_direction};

/// An obstacle or sensor shape, in metres.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// A convex polygon.
    Polygon(ConvexPolygon),
    /// A disc. `radius` should be finite and non-negative (checked by [`Shape::circle`]).
    Circle {
        /// Centre, metres.
        center: DVec2,
        /// Radius, metres.
        radius: f64,
    },
}

impl From<ConvexPolygon> for Shape {
    fn from(polygon: ConvexPolygon) -> Self {
        Shape::Polygon(polygon)
    }
}

impl Shape {
    /// A disc of `radius` metres around `center`; the radius must be finite and non-negative.
    pub fn circle(center: DVec2, radius: f64) -> Result<Self, GeomError> {
        if !(radius.is_finite() && radius >= 0.0) {
            return Err(GeomError::InvalidParameter { what: "radius", value: radius });
        }
        Ok(Shape::Circle { center: sanitize(0, center)?, radius })
    }

    /// Whether `p` lies in the closed shape (boundary included); `false` for non-finite `p`.
    pub fn contains(&self, p: DVec2) -> bool {
        match self {
            Shape::Polygon(poly) => poly.contains(p),
            Shape::Circle { center, radius } => p.is_finite() && (p - *center).length_squared() <= radius * radius,
        }
    }

    /// Distance in metres from `p` to the shape: 0 inside, Euclidean distance outside;
    /// `distance(p) == 0.0` exactly when [`Shape::contains`] holds.
    pub fn distance(&self, p: DVec2) -> f64 {
        match self {
            Shape::Polygon(poly) => poly.distance(p),
            Shape::Circle { .. } => {
                if self.contains(p) {
                    0.0
                } else {
                    let d = self.signed_distance(p);
                    if d.is_nan() { d } else { d.max(f64::MIN_POSITIVE) }
                }
            }
        }
    }

    /// Distance in metres from the segment `a`–`b` to the shape (0 when they touch): the gap a
    /// disc sweeping the segment keeps is this minus its radius.
    pub fn segment_distance(&self, a: DVec2, b: DVec2) -> f64 {
        match self {
            Shape::Polygon(poly) => poly.segment_distance(a, b),
            Shape::Circle { center, radius } => {
                let d = super::closest_on_segment(a, b, *center).distance(*center) - radius;
                if d.is_nan() { d } else { d.max(0.0) }
            }
        }
    }

    /// Signed distance in metres to the boundary: negative inside, positive outside, with the
    /// sign agreeing with [`Shape::contains`].
    pub fn signed_distance(&self, p: DVec2) -> f64 {
        match self {
            Shape::Polygon(poly) => poly.signed_distance(p),
            Shape::Circle { center, radius } => {
                let d = (p - *center).length() - radius;
                if self.contains(p) {
                    d.min(0.0)
                } else if d.is_nan() {
                    d
                } else {
                    d.max(f64::MIN_POSITIVE)
                }
            }
        }
    }

    /// Point of the solid shape closest to `p` (`p` itself when inside), metres.
    pub fn closest_point(&self, p: DVec2) -> DVec2 {
        match self {
            Shape::Polygon(poly) => poly.closest_point(p),
            Shape::Circle { center, radius } => {
                let d = p - *center;
                let len = d.length();
                if len <= *radius { p } else { *center + d * (radius / len) }
            }
        }
    }

    /// Distance in metres along the ray `origin + t·dir` to the first point of the shape, if
    /// within `max_dist`; `Some(0.0)` when `origin` is inside. `dir` is normalised internally.
    pub fn ray_cast(&self, origin: DVec2, dir: DVec2, max_dist: f64) -> Option<f64> {
        match self {
            Shape::Polygon(poly) => poly.ray_cast(origin, dir, max_dist),
            Shape::Circle { center, radius } => {
                let dir = unit_direction(dir)?;
                if !origin.is_finite() || !(max_dist >= 0.0) {
                    return None;
                }
                let m = origin - *center;
                let c = m.length_squared() - radius * radius;
                if c <= 0.0 {
                    return Some(0.0);
                }
                let b = m.dot(dir);
                let disc = b * b - c;
                if b >= 0.0 || !(disc >= 0.0) {
                    return None;
                }
                // Smaller root of t² + 2bt + c = 0, written to avoid cancellation.
                let t = c / (-b + disc.sqrt());
                (t <= max_dist).then_some(t)
            }
        }
    }

    /// Axis-aligned bounding box, metres.
    pub fn aabb(&self) -> Aabb {
        match self {
            Shape::Polygon(poly) => poly.aabb(),
            Shape::Circle { center, radius } => Aabb::around(*center, *radius),
        }
    }

    /// Minimum-area oriented bounding box; for a circle the axis-aligned square around it.
    pub fn obb(&self) -> Obb {
        match self {
            Shape::Polygon(poly) => poly.obb(),
            Shape::Circle { center, radius } => Obb { center: *center, half_extents: DVec2::splat(*radius), yaw: 0.0 },
        }
    }

    /// Area in square metres.
    pub fn area(&self) -> f64 {
        match self {
            Shape::Polygon(poly) => poly.area(),
            Shape::Circle { radius, .. } => std::f64::consts::PI * radius * radius,
        }
    }

    /// Centroid, metres.
    pub fn centroid(&self) -> DVec2 {
        match self {
            Shape::Polygon(poly) => poly.centroid(),
            Shape::Circle { center, .. } => *center,
        }
    }

    /// A polygon outline for drawing: the polygon itself, or for a circle a regular polygon with
    /// `segments` (at least 3) vertices on the circle. Fails for a zero-radius circle.
    pub fn hull_polygon(&self, segments: usize) -> Result<ConvexPolygon, GeomError> {
        match self {
            Shape::Polygon(poly) => Ok(poly.clone()),
            Shape::Circle { center, radius } => {
                let n = segments.clamp(3, 1 << 16);
                let pts: Vec<DVec2> =
                    (0..n).map(|i| *center + DVec2::from_angle(TAU * i as f64 / n as f64) * *radius).collect();
                ConvexPolygon::hull(&pts)
            }
        }
    }

    /// The shape moved by `offset` metres.
    pub fn translated(&self, offset: DVec2) -> Result<Self, GeomError> {
        match self {
            Shape::Polygon(poly) => Ok(Shape::Polygon(poly.translated(offset)?)),
            Shape::Circle { center, radius } => Shape::circle(*center + offset, *radius),
        }
    }

    /// Minkowski sum with a disc of `r` metres: a larger circle, or
    /// [`ConvexPolygon::grown`] with `arc_segments` segments per full turn.
    pub fn grown(&self, r: f64, arc_segments: usize) -> Result<Self, GeomError> {
        match self {
            Shape::Polygon(poly) => Ok(Shape::Polygon(poly.grown(r, arc_segments)?)),
            Shape::Circle { center, radius } => {
                if !(r.is_finite() && r >= 0.0) {
                    return Err(GeomError::InvalidParameter { what: "radius", value: r });
                }
                Shape::circle(*center, radius + r)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> DVec2 {
        DVec2::new(x, y)
    }

    #[test]
    fn circle_queries() {
        let c = Shape::circle(v(1.0, 1.0), 2.0).unwrap();
        assert!(c.contains(v(3.0, 1.0)) && !c.contains(v(3.1, 1.0)));
        assert_eq!(c.distance(v(1.0, 5.0)), 2.0);
        assert_eq!(c.distance(v(1.5, 1.0)), 0.0);
        assert_eq!(c.signed_distance(v(1.5, 1.0)), -1.5);
        assert_eq!(c.closest_point(v(1.0, 5.0)), v(1.0, 3.0));
        assert_eq!(c.closest_point(v(1.5, 1.0)), v(1.5, 1.0));
        assert_eq!(c.ray_cast(v(-5.0, 1.0), v(1.0, 0.0), 10.0), Some(4.0));
        assert_eq!(c.ray_cast(v(-5.0, 1.0), v(1.0, 0.0), 3.0), None);
        assert_eq!(c.ray_cast(v(-5.0, 1.0), v(-1.0, 0.0), 10.0), None);
        assert_eq!(c.ray_cast(v(-5.0, 3.5), v(1.0, 0.0), 10.0), None);
        assert_eq!(c.ray_cast(v(1.0, 0.0), v(1.0, 0.0), 10.0), Some(0.0));
        assert_eq!(c.aabb(), Aabb::new(v(-1.0, -1.0), v(3.0, 3.0)));
        assert_eq!(c.obb().half_extents, v(2.0, 2.0));
        let drawn = c.hull_polygon(32).unwrap();
        assert_eq!(drawn.vertices().len(), 32);
        assert!(drawn.area() < c.area());
        assert!(Shape::circle(v(0.0, 0.0), -1.0).is_err());
        assert!(Shape::circle(v(0.0, 0.0), 0.0).unwrap().hull_polygon(8).is_err());
        assert_eq!(c.grown(1.0, 8).unwrap(), Shape::Circle { center: v(1.0, 1.0), radius: 3.0 });
    }

    #[test]
    fn polygon_delegates() {
        let sq = ConvexPolygon::from_box(v(0.0, 0.0), 2.0, 2.0, 0.0).unwrap();
        let s = Shape::from(sq.clone());
        assert_eq!(s.distance(v(3.0, 0.0)), 2.0);
        assert_eq!(s.ray_cast(v(-3.0, 0.0), v(1.0, 0.0), 5.0), Some(2.0));
        assert_eq!(s.hull_polygon(8).unwrap(), sq);
        assert_eq!(s.aabb(), Aabb::new(v(-1.0, -1.0), v(1.0, 1.0)));
    }
}
