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

impl Obstacle {
    /// Builds an obstacle from its description and vertical extent.
    pub fn build(shape: ObstacleShape, z_min: f64, z_max: f64) -> Result<Obstacle, GeomError> {
        if !(z_min.is_finite() && z_max.is_finite() && z_min < z_max) {
            return Err(GeomError::InvalidParameter { what: "vertical extent (z_min < z_max)", value: z_max - z_min });
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
