//! Planar geometry for obstacle hulls and sensing, and the prisms they sweep in three
//! dimensions ([`Prism`], against the body's [`Capsule`]s).
//!
//! This module is the geometric core of the world: convex obstacle polygons and circles, their
//! distance / containment / ray queries, decomposition of non-convex outlines into convex
//! pieces, axis-aligned boxes, and a spatial index for "what is near here" queries. Seed 000
//! §3.1 describes obstacles by their oriented bounding boxes or convex hulls; DESIGN.md §1 fixes
//! that hulls come from spade's Delaunay triangulation, so [`ConvexPolygon::hull`] and
//! [`decompose`] both go through [`spade`].
//!
//! Units: all coordinates and distances are metres, all angles are radians measured
//! counter-clockwise from the +x axis.
//!
//! Invariants and conventions:
//! - Every [`ConvexPolygon`] has at least 3 vertices, in counter-clockwise order, with no two
//!   consecutive vertices equal and no three consecutive vertices collinear (checked with an
//!   exact orientation predicate, see [`orientation`]).
//! - Coordinates accepted by constructors are finite and at most [`MAX_COORDINATE`] in
//!   magnitude; coordinates smaller than [`TINY_COORDINATE`] in magnitude are flushed to zero.
//!   Within that range the orientation predicate is exact, so containment of polygon vertices and
//!   hull inputs never flips because of rounding.
//! - Queries never panic; degenerate inputs to constructors are reported as [`GeomError`].
//! - Everything is deterministic: no IO, clock, randomness or hash-order dependence.

mod aabb;
mod decompose;
mod index;
mod polygon;
mod predicates;
mod prism;
mod shape;

pub use aabb::Aabb;
pub use decompose::decompose;
pub use index::SpatialIndex;
pub use polygon::{ConvexPolygon, Obb};
pub use predicates::orientation;
pub use prism::{Capsule, Prism};
pub use shape::Shape;

use glam::DVec2;

/// Wraps an angle to `(-π, π]`, radians.
pub fn wrap_angle(a: f64) -> f64 {
    let mut x = a % std::f64::consts::TAU;
    if x <= -std::f64::consts::PI {
        x += std::f64::consts::TAU;
    } else if x > std::f64::consts::PI {
        x -= std::f64::consts::TAU;
    }
    x
}

/// `x.floor() as i64` (saturating, 0 for NaN) without the floating-point floor, which the
/// baseline x86-64 target makes a library call: truncate, then step down when that rounded up.
pub fn floor_i64(x: f64) -> i64 {
    let t = x as i64;
    t.saturating_sub(i64::from(t as f64 > x))
}

/// `3x² − 2x³` on `[0, 1]`, clamped outside: the smooth ramp used by blends and key frames.
pub fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// Largest accepted coordinate magnitude, in metres.
///
/// Keeping coordinates below this bound keeps every product used by the exact orientation
/// predicate far from overflow.
pub const MAX_COORDINATE: f64 = 1e15;

/// Coordinates with a magnitude below this value (in metres) are treated as exactly zero by the
/// constructors. It equals spade's smallest accepted non-zero coordinate.
pub const TINY_COORDINATE: f64 = spade::MIN_ALLOWED_VALUE;

/// Errors reported by geometry constructors.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GeomError {
    /// Fewer distinct points than a polygon needs.
    #[error("need at least 3 distinct points, got {found}")]
    TooFewPoints {
        /// Number of distinct points that were supplied.
        found: usize,
    },
    /// A coordinate was NaN or infinite.
    #[error("point {index} has a non-finite coordinate")]
    NonFinite {
        /// Index of the offending point in the input.
        index: usize,
    },
    /// A coordinate exceeded [`MAX_COORDINATE`] in magnitude.
    #[error("point {index} has coordinate {value} beyond the supported range of ±{MAX_COORDINATE} m")]
    OutOfRange {
        /// Index of the offending point in the input.
        index: usize,
        /// The offending coordinate value, in metres.
        value: f64,
    },
    /// All points lie on one straight line, so they enclose no area.
    #[error("all points are collinear")]
    Collinear,
    /// The same point occurs twice in an outline.
    #[error("points {first} and {second} coincide")]
    RepeatedPoint {
        /// Index of the first occurrence.
        first: usize,
        /// Index of the repeated occurrence.
        second: usize,
    },
    /// Two edges of an outline cross, touch or overlap.
    #[error("outline edges {first} and {second} intersect")]
    SelfIntersecting {
        /// Index of the first edge (edge `i` runs from point `i` to point `i + 1`).
        first: usize,
        /// Index of the second edge.
        second: usize,
    },
    /// A vertex loop handed to [`ConvexPolygon::new`] is not convex (or winds more than once).
    #[error("polygon is not convex at vertex {index}")]
    NotConvex {
        /// Index of a vertex where the loop turns the wrong way.
        index: usize,
    },
    /// A size parameter (width, height, radius, offset) was negative, zero where not allowed, or
    /// non-finite.
    #[error("invalid {what}: {value}")]
    InvalidParameter {
        /// Name of the parameter.
        what: &'static str,
        /// Supplied value.
        value: f64,
    },
    /// More points than a caller's bound allows.
    #[error("{found} points: at most {max}")]
    TooManyPoints {
        /// Number of points supplied.
        found: usize,
        /// The bound.
        max: usize,
    },
    /// The triangulation library rejected the input.
    #[error("triangulation failed: {0}")]
    Triangulation(String),
}

/// Checks one input point and flushes tiny coordinates to zero.
fn sanitize(index: usize, p: DVec2) -> Result<DVec2, GeomError> {
    if !p.is_finite() {
        return Err(GeomError::NonFinite { index });
    }
    let fix = |v: f64| -> Result<f64, GeomError> {
        if v.abs() > MAX_COORDINATE {
            Err(GeomError::OutOfRange { index, value: v })
        } else if v.abs() < TINY_COORDINATE {
            Ok(0.0)
        } else {
            Ok(v)
        }
    };
    Ok(DVec2::new(fix(p.x)?, fix(p.y)?))
}

/// Checks a whole point list, see [`sanitize`].
fn sanitize_all(points: &[DVec2]) -> Result<Vec<DVec2>, GeomError> {
    points.iter().enumerate().map(|(i, &p)| sanitize(i, p)).collect()
}

/// Closest point to `p` on the segment `a`–`b`.
fn closest_on_segment(a: DVec2, b: DVec2, p: DVec2) -> DVec2 {
    let ab = b - a;
    let len2 = ab.length_squared();
    if len2 <= 0.0 {
        return a;
    }
    let t = ((p - a).dot(ab) / len2).clamp(0.0, 1.0);
    a + ab * t
}

/// Normalises a direction; `None` for zero or non-finite input.
fn unit_direction(dir: DVec2) -> Option<DVec2> {
    let len = dir.length();
    if len.is_finite() && len > 0.0 { Some(dir / len) } else { None }
}
