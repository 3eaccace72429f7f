//! The 2D world of seed 000 §3.1 / Fig 2 (DESIGN.md §1): obstacles with convex hulls and
//! oriented bounding boxes in the XY plane (metres), a vertical extent per obstacle, terrain
//! height, and the sensing queries the fuzzy planner needs (distances to obstacle hulls in
//! sectors around the heading, ray casts).
//!
//! Obstacles are stored as convex parts (a non-convex outline is split into convex pieces)
//! in a [`SpatialIndex`], so a query costs what is near the query point, not the whole world.
//!
//! Invariants: a [`World`] only holds valid convex parts with finite coordinates; queries never
//! panic and never depend on hash order; the world does no IO.

pub mod obstacle;
pub mod sensing;
pub mod task;
pub mod terrain;

use glam::DVec2;

use crate::geom::{Aabb, Shape, SpatialIndex};
pub use obstacle::{Obstacle, ObstacleShape};
pub use sensing::{SectorLayout, Sensed};
pub use task::{Pose, Task};
pub use terrain::Terrain;

/// One convex piece of an obstacle, as indexed for queries.
#[derive(Debug, Clone)]
pub struct Part {
    /// Index of the obstacle this piece belongs to.
    pub obstacle: usize,
    /// The convex shape.
    pub shape: Shape,
}

/// The width of a convex shape in its narrowest direction, metres.
fn narrowest_width(shape: &Shape) -> f64 {
    match shape {
        Shape::Circle { radius, .. } => 2.0 * radius,
        Shape::Polygon(p) => {
            let v = p.vertices();
            (0..v.len())
                .map(|i| {
                    let (a, b) = (v[i], v[(i + 1) % v.len()]);
                    let n = (b - a).perp().normalize_or_zero();
                    v.iter().map(|&q| (q - a).dot(n).abs()).fold(0.0, f64::max)
                })
                .fold(f64::INFINITY, f64::min)
        }
    }
}

/// An overhead obstacle with a corner (or its edge, for a round one) this close to a
/// navigation wall is attached to it ([`World::walled_below`]), metres.
pub const ATTACHED_M: f64 = 0.05;

/// Obstacles, their index and the terrain.
#[derive(Debug, Clone)]
pub struct World {
    obstacles: Vec<Obstacle>,
    parts: Vec<Part>,
    index: SpatialIndex,
    bounds: Option<Aabb>,
    /// Ground height over the plane.
    pub terrain: Terrain,
    /// The footstep planner's parameters for characters walking on its terrain.
    pub footsteps: crate::footstep::FootstepParams,
    /// Obstacles above the legs ([`obstacle::Band::Upper`]: overhead bars, shelves), which the
    /// navigation does not see and the upper body plans around.
    pub overhead: Vec<Obstacle>,
}

impl World {
    /// A world holding `obstacles` on flat terrain.
    pub fn new(obstacles: Vec<Obstacle>) -> World {
        let mut parts = Vec::new();
        for (i, o) in obstacles.iter().enumerate() {
            for shape in &o.parts {
                parts.push(Part { obstacle: i, shape: shape.clone() });
            }
        }
        let boxes: Vec<Aabb> = parts.iter().map(|p| p.shape.aabb()).collect();
        let bounds = boxes.iter().copied().reduce(|a, b| a.union(&b));
        let index = SpatialIndex::build(&boxes);
        World {
            obstacles,
            parts,
            index,
            bounds,
            terrain: Terrain::Flat,
            footsteps: Default::default(),
            overhead: Vec::new(),
        }
    }

    /// True when the upper body has something to plan about: an overhead obstacle, or one in
    /// the legs' way that does not stand on the ground as tall as the body.
    pub fn upper_body_matters(&self) -> bool {
        !self.overhead.is_empty() || self.obstacles.iter().any(|o| o.z_min > 0.0 || o.z_max < obstacle::BODY_TOP_M)
    }

    /// The world as navigated by a body that cannot pass under anything lower than
    /// `clear_under_m`: overhead obstacles whose underside is lower become walls of the 2-D
    /// navigation, walked round — those standing free (a bar, a lamp) and those bridging two
    /// walls (a bar across a corridor) — while those attached to one wall ([`ATTACHED_M`]:
    /// shelves, ledges) stay the upper body's, which passes beside them.
    pub fn walled_below(mut self, clear_under_m: f64) -> World {
        let walls: Vec<bool> =
            self.overhead.iter().map(|o| o.z_min < clear_under_m && self.walls_touched(o) != 1).collect();
        if !walls.contains(&true) {
            return self;
        }
        let (mut low, mut high) = (Vec::new(), Vec::new());
        for (o, wall) in std::mem::take(&mut self.overhead).into_iter().zip(walls) {
            if wall { low.push(o) } else { high.push(o) }
        }
        self.with_walls(low, high)
    }

    /// How many of the navigation's obstacles `o` is attached to: those within [`ATTACHED_M`]
    /// of one of its corners (of its edge, for a round one).
    fn walls_touched(&self, o: &Obstacle) -> usize {
        let mut near = Vec::new();
        let mut touched: Vec<usize> = Vec::new();
        let mut touch = |p: DVec2, reach: f64| {
            self.index.query_circle(p, reach, &mut near);
            touched.extend(
                near.iter().filter(|&&i| self.parts[i].shape.distance(p) < reach).map(|&i| self.parts[i].obstacle),
            );
        };
        match &o.hull {
            Shape::Polygon(p) => p.vertices().iter().for_each(|&v| touch(v, ATTACHED_M)),
            Shape::Circle { center, radius } => touch(*center, radius + ATTACHED_M),
        }
        touched.sort_unstable();
        touched.dedup();
        touched.len()
    }

    /// The world as navigated by a walker whose longest step is `step_m`: every convex part of a
    /// hole in the terrain wider than that in every direction (a pond) becomes a wall of the 2-D
    /// navigation, walked round; holes a step can cross, and holes with ground laid over them
    /// later (stepping stones), stay terrain for the footstep planner.
    pub fn walled_holes(mut self, step_m: f64) -> World {
        let features = self.terrain.features();
        // The bounding box of every feature that lays ground (not a hole), in painting order.
        let ground: Vec<Option<crate::geom::Aabb>> = features
            .iter()
            .map(|g| {
                let laid = g.kind != terrain::FeatureKind::Hole;
                laid.then(|| Obstacle::build(g.shape.clone(), 0.0, 1.0).ok().map(|o| o.hull.aabb())).flatten()
            })
            .collect();
        let mut ponds = Vec::new();
        for (k, f) in features.iter().enumerate() {
            if f.kind != terrain::FeatureKind::Hole {
                continue;
            }
            let Ok(hole) = Obstacle::build(f.shape.clone(), obstacle::DEFAULT_Z.0, obstacle::DEFAULT_Z.1) else {
                continue;
            };
            let covered = |part: &Shape| ground[k + 1..].iter().flatten().any(|g| g.intersects(&part.aabb()));
            for part in hole.parts.iter().filter(|p| narrowest_width(p) > step_m && !covered(p)) {
                let shape = match part {
                    Shape::Circle { center, radius } => ObstacleShape::Cylinder { center: *center, radius: *radius },
                    Shape::Polygon(p) => ObstacleShape::Convex { points: p.vertices().to_vec() },
                };
                if let Ok(o) = Obstacle::build(shape, obstacle::DEFAULT_Z.0, obstacle::DEFAULT_Z.1) {
                    ponds.push(o);
                }
            }
        }
        if ponds.is_empty() {
            return self;
        }
        let overhead = std::mem::take(&mut self.overhead);
        self.with_walls(ponds, overhead)
    }

    /// The same world with `walls` added after the navigation's obstacles (in order, so the
    /// walls are the last obstacles) and `overhead` as its overhead ones.
    fn with_walls(self, walls: Vec<Obstacle>, overhead: Vec<Obstacle>) -> World {
        let mut obstacles = self.obstacles;
        obstacles.extend(walls);
        let mut world = World::new(obstacles);
        world.terrain = self.terrain;
        world.footsteps = self.footsteps;
        world.overhead = overhead;
        world
    }

    /// Every obstacle the body can touch: the navigation's and the overhead ones.
    pub fn solids(&self) -> impl Iterator<Item = &Obstacle> {
        self.obstacles.iter().chain(&self.overhead)
    }

    /// The obstacles, in the order given.
    pub fn obstacles(&self) -> &[Obstacle] {
        &self.obstacles
    }

    /// The convex parts of all obstacles.
    pub fn parts(&self) -> &[Part] {
        &self.parts
    }

    /// Bounding box of every obstacle (`None` for an empty world).
    pub fn bounds(&self) -> Option<Aabb> {
        self.bounds
    }

    /// Indices of the parts whose bounding boxes lie within `radius` of `center`.
    pub fn parts_near(&self, center: DVec2, radius: f64, out: &mut Vec<usize>) {
        self.index.query_circle(center, radius, out);
    }

    /// Distance from `p` to the nearest obstacle surface (0 inside), or `max` when nothing is
    /// nearer than `max`.
    pub fn clearance(&self, p: DVec2, max: f64, scratch: &mut Vec<usize>) -> f64 {
        self.index.query_circle(p, max, scratch);
        let mut best = max;
        for &i in scratch.iter() {
            best = best.min(self.parts[i].shape.distance(p));
        }
        best
    }

    /// [`World::ray_cast`] along every ray of an all-around fan from `origin` at once: `rays[k]`
    /// is the unit direction at angle `2πk/n` (`n = rays.len()`), and `out[k]` becomes the
    /// distance to the first obstacle it hits, or infinity when it hits nothing within `max`.
    /// The obstacles within `max` are gathered once, and each is cast only along the rays that
    /// point at its bounding circle, so the cost follows the obstacles nearby, not the rays
    /// times the index's depth. Every hit is the one [`World::ray_cast`] finds.
    pub fn ray_fan(&self, origin: DVec2, rays: &[DVec2], max: f64, scratch: &mut Vec<usize>, out: &mut Vec<f64>) {
        let n = rays.len();
        out.clear();
        out.resize(n, f64::INFINITY);
        if n == 0 {
            return;
        }
        let step = std::f64::consts::TAU / n as f64;
        self.index.query_circle(origin, max, scratch);
        for &i in scratch.iter() {
            let Some(bounds) = self.index.aabb(i) else { continue };
            let to = bounds.center() - origin;
            let (d, r) = (to.length(), 0.5 * (bounds.max - bounds.min).length());
            // The rays that may meet the bounding circle, a ray more each side for rounding.
            let (first, count) = if r < d {
                let half = (r / d).asin();
                let a = to.y.atan2(to.x);
                let lo = ((a - half) / step).floor() as i64 - 1;
                let hi = ((a + half) / step).ceil() as i64 + 1;
                (lo, ((hi - lo + 1) as usize).min(n))
            } else {
                (0, n)
            };
            let shape = &self.parts[i].shape;
            for k in 0..count {
                let k = (first + k as i64).rem_euclid(n as i64) as usize;
                if let Some(t) = shape.ray_cast(origin, rays[k], max)
                    && t < out[k]
                {
                    out[k] = t;
                }
            }
        }
    }

    /// [`World::ray_cast`] along several unit directions `dirs` from one `origin` at once:
    /// `out[k]` becomes the distance along `dirs[k]` to the first obstacle hit, or infinity when
    /// it hits nothing within `max`. The obstacles within `max` are gathered once, and each is
    /// cast only along the rays that pass its bounding circle. Every hit is the one
    /// [`World::ray_cast`] finds.
    pub fn ray_casts(&self, origin: DVec2, dirs: &[DVec2], max: f64, scratch: &mut Vec<usize>, out: &mut [f64]) {
        out.fill(f64::INFINITY);
        self.index.query_circle(origin, max, scratch);
        for &i in scratch.iter() {
            let Some(bounds) = self.index.aabb(i) else { continue };
            let to = bounds.center() - origin;
            let d = to.length();
            // The bounding circle, a little wide for rounding.
            let r = 0.5 * (bounds.max - bounds.min).length() + 1e-9 * (1.0 + d);
            let shape = &self.parts[i].shape;
            for (dir, o) in dirs.iter().zip(out.iter_mut()) {
                let along = to.dot(*dir);
                if along < -r || to.perp_dot(*dir).abs() > r {
                    continue;
                }
                if let Some(t) = shape.ray_cast(origin, *dir, max)
                    && t < *o
                {
                    *o = t;
                }
            }
        }
    }

    /// Distance along the ray from `origin` in unit direction `dir` to the first obstacle hit,
    /// up to `max` (`None`: nothing hit).
    pub fn ray_cast(&self, origin: DVec2, dir: DVec2, max: f64, scratch: &mut Vec<usize>) -> Option<f64> {
        self.index.query_ray(origin, dir, max, scratch);
        let mut best: Option<f64> = None;
        for &i in scratch.iter() {
            if let Some(t) = self.parts[i].shape.ray_cast(origin, dir, max)
                && best.is_none_or(|b| t < b)
            {
                best = Some(t);
            }
        }
        best
    }

    /// Distance from the segment `a`–`b` to the nearest obstacle surface (0 when it touches
    /// one), or `max` when nothing is nearer than `max`.
    pub fn segment_clearance(&self, a: DVec2, b: DVec2, max: f64, scratch: &mut Vec<usize>) -> f64 {
        self.index.query_capsule(a, b, max, scratch);
        let mut best = max;
        for &i in scratch.iter() {
            best = best.min(self.parts[i].shape.segment_distance(a, b));
        }
        best
    }

    /// True when a disc of `radius` sliding from `a` to `b` overlaps no obstacle on the way.
    pub fn sweep_is_free(&self, a: DVec2, b: DVec2, radius: f64, scratch: &mut Vec<usize>) -> bool {
        self.segment_clearance(a, b, radius + 1e-9, scratch) >= radius
    }

    /// True when a disc of `radius` at `p` overlaps no obstacle.
    pub fn is_free(&self, p: DVec2, radius: f64, scratch: &mut Vec<usize>) -> bool {
        self.clearance(p, radius + 1e-9, scratch) >= radius
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn world() -> World {
        World::new(vec![
            Obstacle::build(
                ObstacleShape::Box { center: DVec2::new(5.0, 0.0), width: 2.0, height: 2.0, yaw: 0.0 },
                0.0,
                1.0,
            )
            .unwrap(),
            Obstacle::build(ObstacleShape::Cylinder { center: DVec2::new(0.0, 5.0), radius: 1.0 }, 0.0, 1.0).unwrap(),
        ])
    }

    #[test]
    fn free_overhead_obstacles_below_the_clear_height_become_walls() {
        let overhead = |center: DVec2, z: f64| {
            let shape = ObstacleShape::Box { center, width: 1.0, height: 0.4, yaw: 0.0 };
            Obstacle::build(shape, z, z + 0.1).unwrap()
        };
        let mut w = world();
        // A shelf on the box's side (attached), a free bar as low, a free bar higher up.
        w.overhead = vec![
            overhead(DVec2::new(5.0, 1.2), 1.1),
            overhead(DVec2::new(0.0, 0.0), 1.1),
            overhead(DVec2::new(0.0, -3.0), 1.5),
        ];
        let w = w.walled_below(1.36);
        assert_eq!(w.obstacles().len(), 3);
        assert_eq!(w.obstacles()[2].z_min, 1.1);
        assert!(w.clearance(DVec2::ZERO, 1.0, &mut Vec::new()) == 0.0, "the free low bar is a wall now");
        let kept: Vec<f64> = w.overhead.iter().map(|o| o.hull.aabb().center().y).collect();
        assert_eq!(kept, [1.2, -3.0]);
    }

    #[test]
    fn ponds_too_wide_to_step_across_become_walls() {
        use terrain::{FeatureKind, TerrainFeature};
        let hole = |shape| TerrainFeature::new(shape, FeatureKind::Hole).unwrap();
        let bx = |x: f64, w: f64| ObstacleShape::Box { center: DVec2::new(x, -10.0), width: w, height: 4.0, yaw: 0.0 };
        let mut w = world();
        w.terrain = Terrain::Uneven(vec![
            hole(ObstacleShape::Cylinder { center: DVec2::new(-10.0, 0.0), radius: 1.2 }),
            hole(bx(-20.0, 0.6)),
            hole(bx(-30.0, 3.0)),
            TerrainFeature::new(
                ObstacleShape::Cylinder { center: DVec2::new(-30.0, -10.0), radius: 0.2 },
                FeatureKind::Platform { z_m: 0.0 },
            )
            .unwrap(),
        ]);
        // The pond is walled; the narrow ditch and the stream with a stone laid on it are not.
        let w = w.walled_holes(0.9);
        assert_eq!(w.obstacles().len(), 3);
        let mut scratch = Vec::new();
        assert_eq!(w.clearance(DVec2::new(-10.0, 0.0), 1.0, &mut scratch), 0.0);
        assert!(w.clearance(DVec2::new(-20.0, -10.0), 1.0, &mut scratch) > 0.0);
        assert!(w.clearance(DVec2::new(-30.0, -10.0), 1.0, &mut scratch) > 0.0);
        assert!(
            (narrowest_width(&Shape::Polygon(
                crate::geom::ConvexPolygon::new(&[
                    DVec2::ZERO,
                    DVec2::new(3.0, 0.0),
                    DVec2::new(3.0, 1.0),
                    DVec2::new(0.0, 1.0)
                ])
                .unwrap()
            )) - 1.0)
                .abs()
                < 1e-12
        );
    }

    #[test]
    fn clearance_and_rays() {
        let w = world();
        let mut s = Vec::new();
        assert!((w.clearance(DVec2::ZERO, 100.0, &mut s) - 4.0).abs() < 1e-9);
        assert_eq!(w.clearance(DVec2::new(-50.0, -50.0), 2.0, &mut s), 2.0);
        let hit = w.ray_cast(DVec2::ZERO, DVec2::X, 100.0, &mut s).unwrap();
        assert!((hit - 4.0).abs() < 1e-9);
        assert!(w.ray_cast(DVec2::ZERO, -DVec2::X, 100.0, &mut s).is_none());
        assert!(w.is_free(DVec2::ZERO, 0.3, &mut s));
        assert!(!w.is_free(DVec2::new(3.8, 0.0), 0.3, &mut s));
        // A sweep past the box's corner, and one through it.
        assert!(w.sweep_is_free(DVec2::new(3.0, 1.5), DVec2::new(7.0, 1.5), 0.4, &mut s));
        assert!(!w.sweep_is_free(DVec2::new(3.0, 1.5), DVec2::new(7.0, 1.5), 0.6, &mut s));
        assert!(!w.sweep_is_free(DVec2::new(3.0, 0.0), DVec2::new(7.0, 0.0), 0.1, &mut s));
        let gap = w.segment_clearance(DVec2::new(3.0, 1.5), DVec2::new(7.0, 1.5), 10.0, &mut s);
        assert!((gap - 0.5).abs() < 1e-12, "{gap}");
    }
}
