//! Obstacles (seed 000 §3.1, Fig 2; DESIGN.md §1): boxes, cylinders, convex point sets and
//! non-convex polygons, each with its convex parts, convex hull, oriented bounding box and a
//! vertical extent `[z_min, z_max]`.

use glam::DVec2;

use crate::geom::{ConvexPolygon, GeomError, Obb, Shape, decompose};

/// How an obstacle was described.
#[derive(Debug, Clone, PartialEq)]
pub enum ObstacleShape {
    /// A rectangle: centre, size along its own axes (metres) and yaw (radians).
    Box {
        /// Centre, metres.
        center: DVec2,
        /// Size along the box's x axis, metres.
        width: f64,
        /// Size along the box's y axis, metres.
        height: f64,
        /// Rotation, radians counter-clockwise.
        yaw: f64,
    },
    /// A vertical cylinder: centre and radius, metres.
    Cylinder {
        /// Centre, metres.
        center: DVec2,
        /// Radius, metres.
        radius: f64,
    },
    /// The convex hull of a point set.
    Convex {
        /// The points, metres.
        points: Vec<DVec2>,
    },
    /// A simple (possibly non-convex) polygon, split into convex parts.
    Polygon {
        /// The outline, metres, either orientation.
        outline: Vec<DVec2>,
    },
}

/// An obstacle ready for queries.
#[derive(Debug, Clone, PartialEq)]
pub struct Obstacle {
    /// The description it was built from.
    pub shape: ObstacleShape,
    /// Convex parts whose union is the obstacle.
    pub parts: Vec<Shape>,
    /// Convex hull of the whole obstacle.
    pub hull: Shape,
    /// Minimum-area oriented bounding box.
    pub obb: Obb,
    /// Bottom of the obstacle above the ground, metres.
    pub z_min: f64,
    /// Top of the obstacle, metres.
    pub z_max: f64,
}

/// Default vertical extent of obstacles, metres (taller than a person).
pub const DEFAULT_Z: (f64, f64) = (0.0, 2.0);

/// Highest obstacle top that still counts as ground to step onto or over, metres (the default
/// step-up limit of a person, [`crate::footstep::FootstepParams::max_step_up_m`]).
pub const STEP_ONTO_MAX_Z_M: f64 = 0.45;
/// Lowest bottom of an obstacle that leaves the legs and the pelvis room beneath it, metres:
/// from here up an obstacle belongs to the upper body (seed 002 §5), which bends, twists and
/// moves the arms past it; the 2-D navigation does not see it.
pub const UPPER_BAND_MIN_Z_M: f64 = 1.0;
/// Height of the built-in actor, metres: an obstacle standing on the ground at least this tall
/// is a wall to the whole body, and the upper body has nothing to plan about it.
pub const BODY_TOP_M: f64 = 1.75;

/// Most points one outline (`Convex`, `Polygon`) may have: far more than any obstacle's
/// outline needs, and few enough that splitting it and planning round its pieces stays quick.
/// Refused before any work is done on them.
pub const MAX_OUTLINE_POINTS: usize = 10_000;

/// Which planner an obstacle belongs to (seed 002 §3.2, §5).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Band {
    /// Low enough to step onto or over: terrain for the footstep planner
    /// ([`Obstacle::is_low`]).
    Ground,
    /// In the way of the legs: an obstacle for the 2-D navigation.
    Legs,
    /// Above the legs and the pelvis ([`UPPER_BAND_MIN_Z_M`]): an overhead bar, a shelf, for the
    /// upper-body planner.
    Upper,
}

impl Obstacle {
    /// The planner this obstacle belongs to.
    pub fn band(&self) -> Band {
        if self.is_low() {
            Band::Ground
        } else if self.z_min >= UPPER_BAND_MIN_Z_M {
            Band::Upper
        } else {
            Band::Legs
        }
    }

    /// Whether the obstacle is low enough to be ground: its bottom on the ground and its top at
    /// most [`STEP_ONTO_MAX_Z_M`].
    pub fn is_low(&self) -> bool {
        self.z_min <= 0.0 && self.z_max <= STEP_ONTO_MAX_Z_M
    }

    /// Builds an obstacle from its description and vertical extent.
    pub fn build(shape: ObstacleShape, z_min: f64, z_max: f64) -> Result<Obstacle, GeomError> {
        if !(z_min.is_finite() && z_max.is_finite() && z_min < z_max) {
            return Err(GeomError::InvalidParameter { what: "vertical extent (z_min < z_max)", value: z_max - z_min });
        }
        if let ObstacleShape::Convex { points: outline } | ObstacleShape::Polygon { outline } = &shape
            && outline.len() > MAX_OUTLINE_POINTS
        {
            return Err(GeomError::TooManyPoints { found: outline.len(), max: MAX_OUTLINE_POINTS });
        }
        let parts: Vec<Shape> = match &shape {
            ObstacleShape::Box { center, width, height, yaw } => {
                vec![Shape::Polygon(ConvexPolygon::from_box(*center, *width, *height, *yaw)?)]
            }
            // A cylinder of no width is no obstacle (the text format refuses it too).
            ObstacleShape::Cylinder { radius, .. } if *radius == 0.0 => {
                return Err(GeomError::InvalidParameter { what: "cylinder radius (positive)", value: *radius });
            }
            ObstacleShape::Cylinder { center, radius } => vec![Shape::circle(*center, *radius)?],
            ObstacleShape::Convex { points } => vec![Shape::Polygon(ConvexPolygon::hull(points)?)],
            ObstacleShape::Polygon { outline } => decompose(outline)?.into_iter().map(Shape::Polygon).collect(),
        };
        let hull = match (&shape, parts.as_slice()) {
            (_, [single]) => single.clone(),
            (ObstacleShape::Polygon { outline }, _) => Shape::Polygon(ConvexPolygon::hull(outline)?),
            _ => parts[0].clone(),
        };
        let obb = hull.obb();
        Ok(Obstacle { shape, parts, hull, obb, z_min, z_max })
    }
}
