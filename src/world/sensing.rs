//! Local sensing for the fuzzy planner (seed 000 §3.1, Fig 1 (a), (b)): the free distance to
//! obstacle hulls in angular sectors around the heading, the nearest obstacle in any direction,
//! and the angle and distance to the goal.
//!
//! A sector's distance is exact for convex parts: the nearest point of a convex part inside a
//! wedge is either the part's nearest point (when it lies in the wedge) or the first hit of one
//! of the wedge's two boundary rays. Distances are gaps: measured from the agent's disc, not
//! its centre, and capped at the sensing range.

use glam::DVec2;

use super::World;
use crate::geom::{Shape, wrap_angle};

/// Sector boundaries relative to the heading (radians, ascending, counter-clockwise positive)
/// and the sensing range (metres).
#[derive(Debug, Clone, PartialEq)]
pub struct SectorLayout {
    /// `n + 1` ascending angles bounding `n` sectors, each narrower than π.
    pub edges: Vec<f64>,
    /// Sensing range, metres.
    pub range: f64,
}

impl SectorLayout {
    /// Right, front and left sectors: `[-100°, -25°]`, `[-25°, 25°]`, `[25°, 100°]`, 5 m range.
    pub fn three() -> SectorLayout {
        SectorLayout { edges: [-100.0f64, -25.0, 25.0, 100.0].iter().map(|d| d.to_radians()).collect(), range: 5.0 }
    }

    /// Number of sectors.
    pub fn len(&self) -> usize {
        self.edges.len().saturating_sub(1)
    }

    /// True when there are no sectors.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// What an agent senses at one instant.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Sensed {
    /// Free distance per sector, metres (capped at the range).
    pub sectors: Vec<f64>,
    /// Free distance to the nearest obstacle in any direction, metres (capped at the range).
    pub nearest: f64,
    /// Direction of that nearest obstacle relative to the heading, radians.
    pub nearest_bearing: f64,
    /// Angle from the heading to the goal, radians in `(-π, π]`, positive to the left.
    pub goal_angle: f64,
    /// Distance to the goal point, metres.
    pub goal_distance: f64,
    /// How close to the goal the agent could get by moving straight in some free direction,
    /// metres (TangentBug's reachable distance; the goal distance when nothing better is known).
    pub reachable_goal_distance: f64,
    /// Distance from the goal to the nearest obstacle point seen around the agent, metres
    /// (infinite when none is in range).
    pub obstacle_goal_distance: f64,
    /// Length of the way to the goal the agent remembers, metres (infinite when none is
    /// known); filled by the simulation.
    pub route_distance: f64,
    /// Distance to the point goal seeking steers at: the next waypoint of the remembered way,
    /// or the goal itself (infinite when the simulation gives none: the goal then); filled by
    /// the simulation.
    pub aim_distance: f64,
    /// The remembered way enters a narrow part (a gap, a door, a corridor) just ahead and
    /// goal seeking steers along its line: the way is committed to (false when the simulation
    /// gives none); filled by the simulation.
    pub through_gap: bool,
    /// How many distinct obstacle places the agent has seen so far (grows when it sees
    /// something new); filled by the simulation.
    pub known_obstacles: usize,
    /// Centre of the agent's disc, metres.
    pub position: DVec2,
    /// The goal point, metres.
    pub goal: DVec2,
    /// Heading of the agent (absolute), radians.
    pub heading: f64,
    /// Radius of the agent's disc, metres.
    pub radius: f64,
    /// Sensing range, metres.
    pub range: f64,
    /// Free distance of the disc along rays all around it (ray `i` at absolute angle
    /// `2πi/n`, capped at the range), metres; filled by the simulation's scan, empty when none.
    pub scan: Vec<f64>,
}

/// The sector (bounded by `edges`, as [`SectorLayout::edges`]) the direction `v` (of length `d`)
/// lies in, by its bearing from the heading. When `rays` holds every edge's direction and the
/// edges lie well inside a half turn either way, the side of each edge ray `v` lies on decides
/// it (no arc tangent); a direction within a nanoradian of an edge ray, or any other layout,
/// takes `bearing()` (the arc tangent) and compares it with the edges, which gives the same
/// sector wherever the sides are clear.
fn sector_of(v: DVec2, d: f64, rays: &[DVec2], edges: &[f64], bearing: impl Fn() -> f64) -> Option<usize> {
    let n = edges.len().saturating_sub(1);
    let clear_layout = rays.len() == edges.len()
        && n > 0
        && edges[0] > -std::f64::consts::PI + 1e-6
        && edges[n] < std::f64::consts::PI - 1e-6
        && edges.windows(2).all(|w| w[1] - w[0] < std::f64::consts::PI - 1e-6);
    if clear_layout && d > 0.0 {
        // Left of an edge ray (counter-clockwise from it) when positive.
        let mut side = [0.0f64; 16];
        for (s, r) in side.iter_mut().zip(rays) {
            *s = r.perp_dot(v);
        }
        if side[..=n].iter().all(|s| s.abs() > 1e-9 * d) {
            return (0..n).find(|&k| side[k] > 0.0 && side[k + 1] < 0.0);
        }
    }
    let bearing = bearing();
    (0..n).find(|&k| edges[k] <= bearing && bearing < edges[k + 1])
}

/// Folds one convex shape into the sensed distances: the sectors bounded by `edges` (as
/// [`SectorLayout::edges`]), the wedge boundary `rays` cast up to `range` metres.
fn sense_shape(shape: &Shape, p: DVec2, heading: f64, edges: &[f64], range: f64, rays: &[DVec2], out: &mut Sensed) {
    let c = shape.closest_point(p);
    let d = c.distance(p);
    let inside = shape.contains(p);
    let bearing = || if d > 0.0 { wrap_angle((c - p).to_angle() - heading) } else { 0.0 };
    if d < out.nearest || inside {
        out.nearest = if inside { 0.0 } else { d };
        out.nearest_bearing = bearing();
    }
    if inside {
        out.sectors.iter_mut().for_each(|s| *s = 0.0);
        return;
    }
    // Every point of the shape is at least `d` away, and a ray's hit no nearer than `d` less
    // rounding (far less than the nanometre of slack): the shape can only lower distances
    // above that.
    let lowers = |s: f64| d < s + 1e-9;
    let n = edges.len().saturating_sub(1);
    if !out.sectors.iter().any(|&s| lowers(s)) {
        return;
    }
    if let Some(k) = sector_of(c - p, d, rays, edges, bearing) {
        out.sectors[k] = out.sectors[k].min(d);
    }
    for (j, dir) in rays.iter().enumerate() {
        let before = if j > 0 { out.sectors[j - 1] } else { 0.0 };
        let after = if j < n { out.sectors[j] } else { 0.0 };
        if !lowers(before.max(after)) {
            continue;
        }
        if let Some(t) = shape.ray_cast(p, *dir, range) {
            if j > 0 {
                out.sectors[j - 1] = out.sectors[j - 1].min(t);
            }
            if j < n {
                out.sectors[j] = out.sectors[j].min(t);
            }
        }
    }
}

impl World {
    /// Senses around an agent at `position` with `heading` (radians) and disc `radius`,
    /// seeing the world's obstacles and `others` (other agents as discs: centre, radius).
    /// `scratch` avoids allocation between calls.
    #[allow(clippy::too_many_arguments)]
    pub fn sense(
        &self,
        position: DVec2,
        heading: f64,
        radius: f64,
        goal: DVec2,
        layout: &SectorLayout,
        others: &[(DVec2, f64)],
        scratch: &mut Vec<usize>,
        out: &mut Sensed,
    ) {
        let reach = layout.range + radius;
        out.sectors.clear();
        out.sectors.resize(layout.len(), reach);
        out.nearest = reach;
        out.nearest_bearing = 0.0;
        let mut rays = [DVec2::ZERO; 16];
        let n_rays = layout.edges.len().min(rays.len());
        for (r, a) in rays.iter_mut().zip(&layout.edges) {
            *r = DVec2::from_angle(heading + a);
        }
        self.parts_near(position, reach, scratch);
        for &i in scratch.iter() {
            sense_shape(&self.parts()[i].shape, position, heading, &layout.edges, reach, &rays[..n_rays], out);
        }
        for &(c, r) in others {
            if c.distance(position) - r <= reach
                && let Ok(disc) = Shape::circle(c, r)
            {
                sense_shape(&disc, position, heading, &layout.edges, reach, &rays[..n_rays], out);
            }
        }
        for s in out.sectors.iter_mut() {
            *s = (*s - radius).clamp(0.0, layout.range);
        }
        out.nearest = (out.nearest - radius).clamp(0.0, layout.range);
        out.position = position;
        out.goal = goal;
        out.heading = heading;
        out.radius = radius;
        out.range = layout.range;
        out.goal_distance = position.distance(goal);
        out.route_distance = f64::INFINITY;
        out.aim_distance = f64::INFINITY;
        out.through_gap = false;
        out.goal_angle = if out.goal_distance > 0.0 { wrap_angle((goal - position).to_angle() - heading) } else { 0.0 };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::{Obstacle, ObstacleShape};

    #[test]
    fn sectors_see_the_right_things() {
        // A box straight ahead at x in [4, 6], a cylinder to the left at (0, 3) radius 1.
        let w = World::new(vec![
            Obstacle::build(
                ObstacleShape::Box { center: DVec2::new(5.0, 0.0), width: 2.0, height: 2.0, yaw: 0.0 },
                0.0,
                1.0,
            )
            .unwrap(),
            Obstacle::build(ObstacleShape::Cylinder { center: DVec2::new(0.0, 3.0), radius: 1.0 }, 0.0, 1.0).unwrap(),
        ]);
        let layout = SectorLayout::three();
        let mut out = Sensed::default();
        let mut s = Vec::new();
        w.sense(DVec2::ZERO, 0.0, 0.5, DVec2::new(0.0, -10.0), &layout, &[], &mut s, &mut out);
        assert!((out.sectors[1] - 3.5).abs() < 1e-9, "{out:?}");
        assert!((out.sectors[2] - 1.5).abs() < 1e-9, "{out:?}");
        assert_eq!(out.sectors[0], 5.0);
        assert!((out.nearest - 1.5).abs() < 1e-9);
        assert!((out.goal_angle + std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        // Another agent straight behind is outside every sector but is the nearest.
        w.sense(DVec2::ZERO, 0.0, 0.5, DVec2::X, &layout, &[(DVec2::new(-1.5, 0.0), 0.5)], &mut s, &mut out);
        assert!((out.nearest - 0.5).abs() < 1e-9);
    }

    #[test]
    fn wrap() {
        assert!((wrap_angle(3.0 * std::f64::consts::PI) - std::f64::consts::PI).abs() < 1e-12);
        assert!((wrap_angle(-0.5) + 0.5).abs() < 1e-15);
    }
}
