//! Rims: the circles a shortest path bends round, the straight legs tangent to two of them in
//! closed form, and the arcs of a rim a path may run along.
//!
//! An obstacle part grown by the agent radius `r` is bounded by straight edges and circular
//! arcs: a disc grows into a larger disc, and a convex polygon gets a circle of radius `r` at
//! each corner, of which the arc between the normals of the corner's two edges is part of the
//! grown boundary (its *cone*). A taut path among such shapes is made of straight legs tangent
//! to these circles at both ends and of arcs along them; a leg along a grown straight edge is
//! the tangent of the two corner circles at its ends. A rim of radius 0 is a point (a polygon
//! corner for a point agent, or a path's start and goal).

use std::f64::consts::TAU;

use glam::DVec2;

/// Angular slack (radians) of the tests whether a direction lies on a rim's free arc; it
/// admits the rounding of a tangent computed in closed form and nothing a path could use.
pub(crate) const ANGLE_SLACK: f64 = 1e-12;

/// Which way a path bends round a rim.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Turn {
    /// Counter-clockwise: the rim's centre on the left of the direction of travel.
    Left,
    /// Clockwise: the centre on the right.
    Right,
}

impl Turn {
    /// Both ways, left first.
    pub(crate) const BOTH: [Turn; 2] = [Turn::Left, Turn::Right];

    /// +1 for a left turn (angles grow along the rim), −1 for a right one.
    pub(crate) fn sign(self) -> f64 {
        match self {
            Turn::Left => 1.0,
            Turn::Right => -1.0,
        }
    }
}

/// A circle: centre and radius (0 for a point), metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Circle {
    /// Centre, metres.
    pub(crate) center: DVec2,
    /// Radius, metres.
    pub(crate) radius: f64,
}

impl Circle {
    /// The point of the circle in the direction `angle` (radians) from its centre.
    pub(crate) fn at(&self, angle: f64) -> DVec2 {
        self.center + DVec2::from_angle(angle) * self.radius
    }
}

/// A straight leg tangent to two circles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Tangent {
    /// Where the leg leaves the first circle, metres.
    pub(crate) from: DVec2,
    /// Where it meets the second, metres.
    pub(crate) to: DVec2,
    /// Unit direction from `from` to `to`.
    pub(crate) dir: DVec2,
    /// Unit normal of the first circle at `from` (outward, from its centre).
    pub(crate) leave: DVec2,
    /// Unit normal of the second circle at `to`.
    pub(crate) arrive: DVec2,
    /// Length, metres.
    pub(crate) length: f64,
}

/// The straight leg that leaves circle `a` bending `ta` round it and meets circle `b` bending
/// `tb` round it, in closed form; `None` when there is none (one circle inside the other for
/// equal turns, overlapping circles for opposite ones, coincident centres).
///
/// Travelling in the unit direction `d`, a circle passed bending left lies to the left, so the
/// leg touches it where its outward normal is `right(d)`; bending right, `left(d)`. With
/// `k = σb·ρb − σa·ρa` (σ = +1 left, −1 right) the centres differ by `D = λ·d + k·left(d)`,
/// so `λ = √(|D|² − k²)` is the leg's length and `d = (λ·D − k·left(D)) / |D|²`. Within
/// `slack` metres of touching (`|D| ≥ |k| − slack`) the leg has length 0: a point on a circle
/// leaves it along its tangent, and two circles touching from outside meet at one point.
pub(crate) fn tangent(a: Circle, ta: Turn, b: Circle, tb: Turn, slack: f64) -> Option<Tangent> {
    let between = b.center - a.center;
    let d2 = between.length_squared();
    if !(d2 > 0.0) {
        return None;
    }
    let k = tb.sign() * b.radius - ta.sign() * a.radius;
    let l2 = d2 - k * k;
    let length = if l2 >= 0.0 {
        l2.sqrt()
    } else if d2.sqrt() >= k.abs() - slack {
        0.0
    } else {
        return None;
    };
    let dir = ((between * length - between.perp() * k) / d2).try_normalize()?;
    let right = DVec2::new(dir.y, -dir.x);
    let (leave, arrive) = (right * ta.sign(), right * tb.sign());
    Some(Tangent { from: a.center + leave * a.radius, to: b.center + arrive * b.radius, dir, leave, arrive, length })
}

/// The directions (angles of outward normals, radians) in which a rim's boundary is free: the
/// whole circle, or arcs of it, each `(start, width)` counter-clockwise with `width < 2π`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum FreeArcs {
    /// Every direction.
    Whole,
    /// These arcs (none: the rim is nowhere free).
    Arcs(Box<[(f64, f64)]>),
}

/// Where a direction lies on a rim's free arcs: the arc and the angle from its start
/// (for [`FreeArcs::Whole`], arc 0 and the direction itself).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Spot {
    arc: usize,
    offset: f64,
}

impl FreeArcs {
    /// Whether no direction is free.
    pub(crate) fn is_empty(&self) -> bool {
        matches!(self, FreeArcs::Arcs(a) if a.is_empty())
    }

    /// The free arc holding the direction `angle` (radians), within [`ANGLE_SLACK`].
    pub(crate) fn locate(&self, angle: f64) -> Option<Spot> {
        match self {
            FreeArcs::Whole => Some(Spot { arc: 0, offset: angle }),
            FreeArcs::Arcs(arcs) => arcs.iter().enumerate().find_map(|(arc, &(start, width))| {
                let offset = (angle - start + ANGLE_SLACK).rem_euclid(TAU) - ANGLE_SLACK;
                (offset <= width + ANGLE_SLACK).then_some(Spot { arc, offset })
            }),
        }
    }

    /// The angle (radians, ≥ 0) a path turns through running along the rim from `from` to
    /// `to` bending `turn`, staying on one free arc; `None` when it would leave the arc.
    pub(crate) fn sweep(&self, from: Spot, to: Spot, turn: Turn) -> Option<f64> {
        match self {
            FreeArcs::Whole => {
                let sweep = (turn.sign() * (to.offset - from.offset)).rem_euclid(TAU);
                // A leg that leaves where the path arrived comes back round as a full turn.
                Some(if sweep > TAU - ANGLE_SLACK { 0.0 } else { sweep })
            }
            FreeArcs::Arcs(_) => {
                let sweep = turn.sign() * (to.offset - from.offset);
                (from.arc == to.arc && sweep >= -ANGLE_SLACK).then_some(sweep.max(0.0))
            }
        }
    }

    /// The free arcs of the directions `start + t`, `t ∈ [0, width]` (the whole circle for
    /// `width ≥ 2π`), cut at `cuts` (angles, radians, in any order; cuts outside the range are
    /// ignored, and cutting more finely never changes the result), keeping the pieces whose
    /// middle direction `blocked` does not reject. Touching pieces are merged.
    pub(crate) fn of(start: f64, width: f64, cuts: &mut [f64], blocked: impl Fn(f64) -> bool) -> FreeArcs {
        let whole = width >= TAU;
        let width = width.min(TAU);
        let mut offsets: Vec<f64> =
            cuts.iter_mut().map(|c| (*c - start).rem_euclid(TAU)).filter(|t| *t > 0.0 && *t < width).collect();
        offsets.sort_by(f64::total_cmp);
        offsets.dedup();
        if whole && offsets.is_empty() {
            return if blocked(start) { FreeArcs::Arcs(Box::new([])) } else { FreeArcs::Whole };
        }
        let mut bounds = Vec::with_capacity(offsets.len() + 2);
        bounds.push(0.0);
        bounds.extend(offsets);
        bounds.push(width);
        let mut free: Vec<(f64, f64)> = Vec::new();
        for w in bounds.windows(2) {
            if blocked(start + 0.5 * (w[0] + w[1])) {
                continue;
            }
            match free.last_mut() {
                Some(last) if last.1 == w[0] => last.1 = w[1],
                _ => free.push((w[0], w[1])),
            }
        }
        if whole && free.len() > 1 && free[0].0 == 0.0 && free.last().is_some_and(|l| l.1 == TAU) {
            // The first and last pieces meet across the start.
            let (lo, _) = free.pop().unwrap_or((0.0, 0.0));
            free[0].0 = lo - TAU;
        }
        if whole && free.len() == 1 && free[0] == (0.0, TAU) {
            return FreeArcs::Whole;
        }
        FreeArcs::Arcs(free.into_iter().map(|(lo, hi)| (start + lo, hi - lo)).collect())
    }
}

/// The angle of `v` in `(-π, π]`, radians.
pub(crate) fn angle_of(v: DVec2) -> f64 {
    v.y.atan2(v.x)
}

/// Angles `center_angle ± acos(cosine)` where a circle meets a boundary it crosses (none when
/// `|cosine| > 1`).
pub(crate) fn crossings(center_angle: f64, cosine: f64, out: &mut Vec<f64>) {
    if cosine.abs() <= 1.0 {
        let half = cosine.acos();
        out.extend([center_angle - half, center_angle + half]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn c(x: f64, y: f64, r: f64) -> Circle {
        Circle { center: DVec2::new(x, y), radius: r }
    }

    #[test]
    fn tangents_touch_both_circles_on_the_side_of_their_turn() {
        let (a, b) = (c(0.0, 0.0, 0.5), c(4.0, 1.0, 1.2));
        for ta in Turn::BOTH {
            for tb in Turn::BOTH {
                let t = tangent(a, ta, b, tb, 0.0).unwrap();
                let dir = (t.to - t.from) / t.length;
                assert!((t.length - t.from.distance(t.to)).abs() < 1e-12);
                // Touching: the leg is square to both normals, the points on the circles.
                assert!(dir.dot(t.leave).abs() < 1e-12 && dir.dot(t.arrive).abs() < 1e-12);
                assert!((t.from.distance(a.center) - a.radius).abs() < 1e-12);
                assert!((t.to.distance(b.center) - b.radius).abs() < 1e-12);
                // The centre lies on the side of the turn.
                for (circle, turn) in [(a, ta), (b, tb)] {
                    let side = dir.perp_dot(circle.center - t.from);
                    assert!(side * turn.sign() > 0.0 || circle.radius == 0.0, "{ta:?} {tb:?}");
                }
            }
        }
        // From a point outside a circle: √(d² − ρ²).
        let t = tangent(c(0.0, 0.0, 0.0), Turn::Left, c(5.0, 0.0, 1.0), Turn::Left, 0.0).unwrap();
        assert!((t.length - 24f64.sqrt()).abs() < 1e-12 && t.to.y < 0.0);
        // Nested circles have no outer leg, overlapping ones no inner leg.
        assert!(tangent(c(0.0, 0.0, 2.0), Turn::Left, c(0.5, 0.0, 1.0), Turn::Left, 0.0).is_none());
        assert!(tangent(c(0.0, 0.0, 1.0), Turn::Left, c(1.5, 0.0, 1.0), Turn::Right, 0.0).is_none());
        // A point on a circle leaves along its tangent.
        let t = tangent(c(1.0, 0.0, 0.0), Turn::Left, c(0.0, 0.0, 1.0), Turn::Left, 1e-12).unwrap();
        assert_eq!(t.length, 0.0);
        assert!((t.to - DVec2::new(1.0, 0.0)).length() < 1e-12);
    }

    #[test]
    fn free_arcs_cut_and_merge() {
        // A quarter cone with a blocked middle.
        let arcs = FreeArcs::of(0.0, PI / 2.0, &mut [0.5, 1.0, 7.0], |a| a > 0.5 && a < 1.0);
        assert_eq!(arcs, FreeArcs::Arcs(Box::new([(0.0, 0.5), (1.0, PI / 2.0 - 1.0)])));
        let on = arcs.locate(0.2).unwrap();
        let late = arcs.locate(0.4).unwrap();
        assert!(arcs.locate(0.7).is_none());
        assert_eq!(arcs.sweep(on, late, Turn::Left), Some(0.4 - 0.2));
        assert_eq!(arcs.sweep(on, late, Turn::Right), None);
        assert_eq!(arcs.sweep(on, arcs.locate(1.2).unwrap(), Turn::Left), None);
        // A whole circle free across its start joins its two free ends.
        let ring = FreeArcs::of(-PI, TAU, &mut [-0.3, 0.3], |a| a.abs() < 0.3);
        let FreeArcs::Arcs(a) = &ring else { panic!("{ring:?}") };
        assert_eq!(a.len(), 1);
        assert!((a[0].0 - 0.3).rem_euclid(TAU) < 1e-12 && (a[0].1 - (TAU - 0.6)).abs() < 1e-12, "{a:?}");
        assert!(ring.locate(PI).is_some() && ring.locate(0.0).is_none());
        assert_eq!(FreeArcs::of(-PI, TAU, &mut [], |_| false), FreeArcs::Whole);
        assert!(FreeArcs::of(-PI, TAU, &mut [], |_| true).is_empty());
        // Round the whole circle: grazing (leaving where it arrived) turns through nothing.
        let w = FreeArcs::Whole;
        let at = w.locate(1.0).unwrap();
        assert_eq!(w.sweep(at, w.locate(1.0 - 1e-15).unwrap(), Turn::Left), Some(0.0));
        assert!((w.sweep(at, w.locate(-1.0).unwrap(), Turn::Left).unwrap() - (TAU - 2.0)).abs() < 1e-12);
    }
}
