//! Geometric boundary following over the all-around scan (TangentBug-style, seed 000 §3.1,
//! DESIGN.md §2): the direction that keeps one obstacle contour on a fixed side.
//!
//! The scan's obstacles are grown by a clearance margin and every ray is judged by how far the
//! grown disc could travel along it ([`swept_free`]); a ray is open when that is at
//! least a look-ahead distance. Starting from the nearest obstacle ray on the followed side,
//! the rays are swept away from the wall (clockwise for a wall on the left); the first open ray
//! is the direction to move in. Along a straight wall this converges on the wall's tangent at
//! the clearance margin (the look-ahead sets how quickly), at a concave corner it turns away
//! from the wall, and past a convex corner it keeps turning around the corner, so the agent
//! stays with one contour. Gaps too narrow for the grown disc count as wall, so the follower
//! does not try them; when nothing is open with the margin, the bare disc is tried.

use super::sense::{Fan, swept_free, swept_free_ahead};
use crate::geom::wrap_angle;

/// Which side the followed boundary is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// Obstacle on the left.
    Left,
    /// Obstacle on the right.
    Right,
}

/// Tuning of the geometric follower. Every field documents its default.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FollowParams {
    /// Gap kept between the disc and the followed wall, metres (0.08).
    pub clearance_m: f64,
    /// Free travel a ray needs to count as open, metres (0.5).
    pub lookahead_m: f64,
    /// The reference wall ray is searched this far past the heading on the side away from the
    /// wall, degrees (30).
    pub window_deg: f64,
}

impl Default for FollowParams {
    fn default() -> Self {
        FollowParams { clearance_m: 0.08, lookahead_m: 0.5, window_deg: 30.0 }
    }
}

/// What the follower proposes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FollowStep {
    /// Absolute direction to move in, radians.
    pub direction: f64,
    /// How far the disc could travel that way (bare disc), metres.
    pub free_m: f64,
    /// Gap to the followed wall (the reference ray), metres.
    pub wall_m: f64,
    /// Direction of the followed wall's nearest point (the reference ray), absolute, radians.
    pub wall_direction: f64,
}

/// The boundary-following direction for an agent heading `heading` (absolute, radians) with
/// the followed wall on `side`, from the all-around `scan` of free distances (ray `i` at
/// absolute angle `2πi/n`, capped at `range`). `None` when no obstacle is in range on the
/// followed side (the wall is lost) or the scan is empty.
pub fn follow_direction(
    scan: &[f64],
    heading: f64,
    side: Side,
    radius: f64,
    range: f64,
    p: &FollowParams,
) -> Option<FollowStep> {
    let n = scan.len();
    if n == 0 {
        return None;
    }
    let step = std::f64::consts::TAU / n as f64;
    // +1: sweep counter-clockwise (wall on the right), -1: clockwise (wall on the left).
    let (toward, sweep): (f64, isize) = match side {
        Side::Left => (1.0, -1),
        Side::Right => (-1.0, 1),
    };
    // The reference: the nearest obstacle ray on the followed side of the heading.
    let window = p.window_deg.to_radians();
    let mut reference: Option<usize> = None;
    for (i, &f) in scan.iter().enumerate() {
        if f >= range {
            continue;
        }
        let rel = wrap_angle(step * i as f64 - heading) * toward;
        if rel < -window || rel > std::f64::consts::PI - 1e-9 {
            continue;
        }
        if reference.is_none_or(|r| f < scan[r]) {
            reference = Some(i);
        }
    }
    let reference = reference?;
    let bare = swept_free(scan, radius, range);
    let grown_scan: Vec<f64> = scan.iter().map(|f| (f - p.clearance_m).max(0.0)).collect();
    let grown = swept_free(&grown_scan, radius + p.clearance_m, range);
    let pick = |free: &[f64]| -> Option<usize> {
        (0..n as isize).map(|k| (reference as isize + sweep * k).rem_euclid(n as isize) as usize).find(|&i| {
            let need = p.lookahead_m.min(range);
            free[i] >= need
        })
    };
    let i = pick(&grown).or_else(|| pick(&bare))?;
    Some(FollowStep {
        direction: step * i as f64,
        free_m: bare[i],
        wall_m: scan[reference],
        wall_direction: step * reference as f64,
    })
}

/// How far the agent's disc, kept `clearance` metres off every obstacle, could travel straight
/// along `heading` (absolute, radians) by the all-around `scan`: the smaller swept free
/// distance of the two rays around the heading, metres; `None` for an empty scan.
pub fn swept_ahead(scan: &[f64], heading: f64, radius: f64, clearance: f64, range: f64) -> Option<f64> {
    let n = scan.len();
    if n == 0 {
        return None;
    }
    let step = std::f64::consts::TAU / n as f64;
    let lo = ((heading.rem_euclid(std::f64::consts::TAU) / step).floor() as usize) % n;
    let fan = Fan::of(n);
    // The two rays of [`swept_free`] around the heading, for the grown disc (obstacle
    // points stay where the scan saw them).
    let along_ray = |i: usize| swept_free_ahead(scan, i, radius, radius + clearance, range, &fan.turns);
    Some(along_ray(lo).min(along_ray((lo + 1) % n)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    /// A scan of a straight wall `gap` metres from the disc along the line y = -(gap + r)
    /// (below the agent), as seen from the origin.
    fn wall_below(gap: f64, r: f64, n: usize, range: f64) -> Vec<f64> {
        (0..n)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / n as f64;
                let dir = DVec2::from_angle(a);
                if dir.y < -1e-9 { ((gap + r) / -dir.y - r).clamp(0.0, range) } else { range }
            })
            .collect()
    }

    #[test]
    fn follows_a_straight_wall_along_its_tangent() {
        let p = FollowParams::default();
        // Wall on the right, heading +x: the direction is along +x, turned a little toward the
        // wall when far from it, never into it when at the margin.
        let scan = wall_below(p.clearance_m, 0.3, 72, 5.0);
        let s = follow_direction(&scan, 0.0, Side::Right, 0.3, 5.0, &p).unwrap();
        assert!(wrap_angle(s.direction).abs() < 0.1, "{s:?}");
        let scan = wall_below(1.0, 0.3, 72, 5.0);
        let s = follow_direction(&scan, 0.0, Side::Right, 0.3, 5.0, &p).unwrap();
        let d = wrap_angle(s.direction);
        assert!(d < -0.3 && d > -1.6, "{s:?}");
        // The same wall followed on the left while heading -x.
        let scan = wall_below(p.clearance_m, 0.3, 72, 5.0);
        let s = follow_direction(&scan, std::f64::consts::PI, Side::Left, 0.3, 5.0, &p).unwrap();
        assert!(wrap_angle(s.direction - std::f64::consts::PI).abs() < 0.1, "{s:?}");
        // Nothing on the followed side: the wall is lost.
        let empty = vec![5.0; 72];
        assert!(follow_direction(&empty, 0.0, Side::Left, 0.3, 5.0, &p).is_none());
    }
}
