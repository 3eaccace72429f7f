//! Convex polygons and oriented bounding boxes.

use std::cmp::Ordering;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

use glam::DVec2;
use spade::{DelaunayTriangulation, Point2, Triangulation};

use super::{Aabb, GeomError, closest_on_segment, orientation, sanitize, sanitize_all, unit_direction};

/// A convex polygon in the plane, coordinates in metres.
///
/// Invariants (upheld by every constructor): at least 3 vertices, counter-clockwise order, no
/// repeated consecutive vertices, no three consecutive vertices collinear, strictly convex,
/// winding once, coordinates finite and within [`super::MAX_COORDINATE`].
#[derive(Debug, Clone, PartialEq)]
pub struct ConvexPolygon {
    vertices: Vec<DVec2>,
}

/// Oriented bounding box: a rectangle of half extents `half_extents` (metres) centred on `center`
/// (metres) whose local x axis points along `yaw` (radians, counter-clockwise from +x).
///
/// Boxes produced by [`ConvexPolygon::obb`] have `half_extents.x >= half_extents.y` and
/// `yaw` in `(-π/2, π/2]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Obb {
    /// Centre of the box, metres.
    pub center: DVec2,
    /// Half the side lengths along the local x and y axes, metres.
    pub half_extents: DVec2,
    /// Direction of the local x axis, radians counter-clockwise from world +x.
    pub yaw: f64,
}

impl Obb {
    /// Unit vectors of the local x and y axes in world coordinates.
    pub fn axes(&self) -> (DVec2, DVec2) {
        let x = DVec2::from_angle(self.yaw);
        (x, x.perp())
    }

    /// The four corners in counter-clockwise order, metres.
    pub fn corners(&self) -> [DVec2; 4] {
        let (ax, ay) = self.axes();
        let ex = ax * self.half_extents.x;
        let ey = ay * self.half_extents.y;
        [self.center - ex - ey, self.center + ex - ey, self.center + ex + ey, self.center - ex + ey]
    }

    /// Area in square metres.
    pub fn area(&self) -> f64 {
        4.0 * self.half_extents.x * self.half_extents.y
    }

    /// Whether `p` lies in the closed box (up to floating-point rounding).
    pub fn contains(&self, p: DVec2) -> bool {
        let (ax, ay) = self.axes();
        let d = p - self.center;
        d.dot(ax).abs() <= self.half_extents.x && d.dot(ay).abs() <= self.half_extents.y
    }

    /// The box as a polygon; fails for a degenerate (zero-width) box.
    pub fn to_polygon(&self) -> Result<ConvexPolygon, GeomError> {
        ConvexPolygon::from_box(self.center, 2.0 * self.half_extents.x, 2.0 * self.half_extents.y, self.yaw)
    }
}

impl ConvexPolygon {
    /// Polygon from a convex vertex loop in either orientation (metres).
    ///
    /// Consecutive duplicates and vertices lying on the straight segment between their
    /// neighbours are dropped; the loop must otherwise turn the same way at every vertex and
    /// wind exactly once.
    pub fn new(vertices: &[DVec2]) -> Result<Self, GeomError> {
        Self::from_loop(sanitize_all(vertices)?)
    }

    /// Convex hull of `points` (metres), computed from spade's Delaunay triangulation by walking
    /// its convex-hull edges.
    ///
    /// Interior points, duplicates and points in the middle of hull edges are ignored. Fails with
    /// [`GeomError::NonFinite`] / [`GeomError::OutOfRange`] for bad coordinates,
    /// [`GeomError::TooFewPoints`] for fewer than 3 distinct points and [`GeomError::Collinear`]
    /// when all points lie on one line.
    pub fn hull(points: &[DVec2]) -> Result<Self, GeomError> {
        let pts = sanitize_all(points)?;
        let tri = DelaunayTriangulation::<Point2<f64>>::bulk_load(pts.iter().map(|p| Point2::new(p.x, p.y)).collect())
            .map_err(|e| GeomError::Triangulation(e.to_string()))?;
        if tri.num_vertices() < 3 {
            return Err(GeomError::TooFewPoints { found: tri.num_vertices() });
        }
        if tri.all_vertices_on_line() {
            return Err(GeomError::Collinear);
        }
        let ring: Vec<DVec2> = tri
            .convex_hull()
            .map(|edge| {
                let p = edge.from().position();
                DVec2::new(p.x, p.y)
            })
            .collect();
        Self::from_loop(ring)
    }

    /// Rectangle of `width` × `height` metres centred on `center`, its width axis rotated by
    /// `yaw_rad` radians counter-clockwise from +x.
    pub fn from_box(center: DVec2, width: f64, height: f64, yaw_rad: f64) -> Result<Self, GeomError> {
        for (what, value) in [("width", width), ("height", height)] {
            if !(value.is_finite() && value > 0.0) {
                return Err(GeomError::InvalidParameter { what, value });
            }
        }
        if !yaw_rad.is_finite() {
            return Err(GeomError::InvalidParameter { what: "yaw", value: yaw_rad });
        }
        let center = sanitize(0, center)?;
        let obb = Obb { center, half_extents: DVec2::new(width * 0.5, height * 0.5), yaw: yaw_rad };
        Self::from_loop(sanitize_all(&obb.corners())?)
    }

    /// Builds a polygon from sanitized points forming a convex loop, cleaning it up.
    pub(super) fn from_loop(mut pts: Vec<DVec2>) -> Result<Self, GeomError> {
        pts.dedup();
        while pts.len() > 1 && pts.first() == pts.last() {
            pts.pop();
        }
        if pts.len() < 3 {
            return Err(GeomError::TooFewPoints { found: pts.len() });
        }
        // Drop vertices lying on the segment between their neighbours; a collinear vertex where
        // the loop doubles back is not convex.
        loop {
            let n = pts.len();
            let mut kept = Vec::with_capacity(n);
            for i in 0..n {
                let (prev, cur, next) = (pts[(i + n - 1) % n], pts[i], pts[(i + 1) % n]);
                if orientation(prev, cur, next) == Ordering::Equal {
                    if (cur - prev).dot(next - cur) < 0.0 {
                        return Err(GeomError::NotConvex { index: i });
                    }
                } else {
                    kept.push(cur);
                }
            }
            if kept.len() == n {
                break;
            }
            if kept.len() < 3 {
                return Err(GeomError::Collinear);
            }
            pts = kept;
        }
        let n = pts.len();
        let turn = |i: usize| orientation(pts[(i + n - 1) % n], pts[i], pts[(i + 1) % n]);
        let first = turn(0);
        if let Some(bad) = (1..n).find(|&i| turn(i) != first) {
            return Err(GeomError::NotConvex { index: bad });
        }
        if first == Ordering::Less {
            pts.reverse();
        }
        // All turns agree; make sure the loop winds once (a pentagram turns left everywhere too).
        let total_turn: f64 = (0..n)
            .map(|i| {
                let e0 = pts[i] - pts[(i + n - 1) % n];
                let e1 = pts[(i + 1) % n] - pts[i];
                e0.perp_dot(e1).atan2(e0.dot(e1))
            })
            .sum();
        if total_turn > 1.5 * TAU {
            return Err(GeomError::NotConvex { index: 0 });
        }
        Ok(Self { vertices: pts })
    }

    /// Vertices in counter-clockwise order, metres.
    pub fn vertices(&self) -> &[DVec2] {
        &self.vertices
    }

    /// Edges as `(start, end)` pairs in counter-clockwise order; the interior is on the left.
    pub fn edges(&self) -> impl Iterator<Item = (DVec2, DVec2)> + '_ {
        let n = self.vertices.len();
        (0..n).map(move |i| (self.vertices[i], self.vertices[(i + 1) % n]))
    }

    /// Whether `p` lies in the closed polygon (boundary included). Exact for coordinates in the
    /// supported range; `false` for non-finite `p`.
    pub fn contains(&self, p: DVec2) -> bool {
        p.is_finite() && self.edges().all(|(a, b)| orientation(a, b, p) != Ordering::Less)
    }

    /// Closest boundary point to `p` and its distance, metres.
    fn nearest_on_boundary(&self, p: DVec2) -> (DVec2, f64) {
        let mut best = (self.vertices[0], f64::INFINITY);
        for (a, b) in self.edges() {
            let q = closest_on_segment(a, b, p);
            let d = q.distance(p);
            if d < best.1 {
                best = (q, d);
            }
        }
        best
    }

    /// Distance in metres from `p` to the polygon: 0 inside or on the boundary, Euclidean
    /// distance to the boundary outside. NaN for a NaN point.
    ///
    /// `distance(p) == 0.0` exactly when [`ConvexPolygon::contains`] holds: a point outside by
    /// less than rounding reports the smallest positive `f64` rather than 0.
    pub fn distance(&self, p: DVec2) -> f64 {
        if !p.is_finite() {
            return if p.is_nan() { f64::NAN } else { f64::INFINITY };
        }
        if self.contains(p) { 0.0 } else { self.nearest_on_boundary(p).1.max(f64::MIN_POSITIVE) }
    }

    /// Signed distance in metres from `p` to the boundary: negative inside, positive outside,
    /// zero on the boundary. NaN for a NaN point. Its sign agrees with [`ConvexPolygon::contains`]
    /// (non-positive exactly for contained points).
    pub fn signed_distance(&self, p: DVec2) -> f64 {
        if !p.is_finite() {
            return if p.is_nan() { f64::NAN } else { f64::INFINITY };
        }
        let d = self.nearest_on_boundary(p).1;
        if self.contains(p) { 0.0 - d } else { d.max(f64::MIN_POSITIVE) }
    }

    /// Distance in metres from the segment `a`–`b` to the polygon: 0 when the segment touches
    /// it, else the smallest distance between an endpoint and the polygon or a vertex and the
    /// segment (exact for a convex polygon). NaN when an endpoint is NaN.
    pub fn segment_distance(&self, a: DVec2, b: DVec2) -> f64 {
        let (da, db) = (self.distance(a), self.distance(b));
        if da == 0.0 || db == 0.0 || da.is_nan() || db.is_nan() {
            return if da.is_nan() || db.is_nan() { f64::NAN } else { 0.0 };
        }
        // Both ends outside: the segment touches the polygon only if it crosses an edge.
        let crosses = self.edges().any(|(p, q)| {
            let (o1, o2) = (orientation(a, b, p), orientation(a, b, q));
            let (o3, o4) = (orientation(p, q, a), orientation(p, q, b));
            o1 != o2 && o3 != o4
        });
        if crosses {
            return 0.0;
        }
        let mut d = da.min(db);
        for &v in &self.vertices {
            d = d.min(closest_on_segment(a, b, v).distance(v));
        }
        d.max(f64::MIN_POSITIVE)
    }

    /// Point of the (solid) polygon closest to `p`: `p` itself when inside, otherwise the
    /// nearest boundary point. Metres.
    pub fn closest_point(&self, p: DVec2) -> DVec2 {
        if self.contains(p) { p } else { self.nearest_on_boundary(p).0 }
    }

    /// Boundary point closest to `p`, also for `p` inside. Metres.
    pub fn closest_boundary_point(&self, p: DVec2) -> DVec2 {
        self.nearest_on_boundary(p).0
    }

    /// Distance in metres along the ray `origin + t·dir` to the first point of the polygon, if
    /// it is within `max_dist` metres.
    ///
    /// `dir` is normalised internally (it should be a unit vector; a zero or non-finite `dir`
    /// gives `None`). Returns `Some(0.0)` exactly when `origin` is inside the polygon.
    pub fn ray_cast(&self, origin: DVec2, dir: DVec2, max_dist: f64) -> Option<f64> {
        let dir = unit_direction(dir)?;
        if !origin.is_finite() || !(max_dist >= 0.0) {
            return None;
        }
        if self.contains(origin) {
            return Some(0.0);
        }
        let mut t_enter = 0.0f64;
        let mut t_exit = max_dist;
        for (a, b) in self.edges() {
            let e = b - a;
            let outward = DVec2::new(e.y, -e.x);
            let num = outward.dot(a - origin);
            let den = outward.dot(dir);
            if den == 0.0 {
                if num < 0.0 {
                    return None;
                }
            } else if den < 0.0 {
                t_enter = t_enter.max(num / den);
            } else {
                t_exit = t_exit.min(num / den);
            }
            if t_enter > t_exit {
                return None;
            }
        }
        // The origin is outside, so report a positive distance even if rounding produced 0.
        Some(t_enter.max(f64::MIN_POSITIVE))
    }

    /// Axis-aligned bounding box, metres.
    pub fn aabb(&self) -> Aabb {
        let mut b = Aabb::new(self.vertices[0], self.vertices[0]);
        for &v in &self.vertices[1..] {
            b = Aabb::new(b.min.min(v), b.max.max(v));
        }
        b
    }

    /// Minimum-area oriented bounding box, found with rotating calipers (one side of the optimal
    /// box is flush with a polygon edge). Ties go to the lowest edge index.
    pub fn obb(&self) -> Obb {
        let v = &self.vertices;
        let n = v.len();
        let dot_at = |i: usize, d: DVec2| v[i % n].dot(d);
        let edge_dir = |i: usize| (v[(i + 1) % n] - v[i]).normalize_or_zero();
        let argmax = |d: DVec2| (1..n).fold(0, |best, i| if dot_at(i, d) > dot_at(best, d) { i } else { best });

        let d0 = edge_dir(0);
        let (mut right, mut top, mut left) = (argmax(d0), argmax(d0.perp()), argmax(-d0));
        let advance = |idx: &mut usize, d: DVec2| {
            for _ in 0..n {
                if dot_at(*idx + 1, d) > dot_at(*idx, d) {
                    *idx = (*idx + 1) % n;
                } else {
                    break;
                }
            }
        };

        let mut best: Option<(f64, Obb)> = None;
        for i in 0..n {
            let d = edge_dir(i);
            let up = d.perp();
            advance(&mut right, d);
            advance(&mut top, up);
            advance(&mut left, -d);
            let base = v[i];
            let lo = (v[left] - base).dot(d);
            let hi = (v[right] - base).dot(d);
            let height = (v[top] - base).dot(up).max(0.0);
            let width = (hi - lo).max(0.0);
            let area = width * height;
            if best.as_ref().is_none_or(|(a, _)| area < *a) {
                let center = base + d * ((lo + hi) * 0.5) + up * (height * 0.5);
                let obb = Obb { center, half_extents: DVec2::new(width * 0.5, height * 0.5), yaw: d.y.atan2(d.x) };
                best = Some((area, obb));
            }
        }
        let mut obb = best.map_or(Obb { center: v[0], half_extents: DVec2::ZERO, yaw: 0.0 }, |(_, o)| o);
        if obb.half_extents.y > obb.half_extents.x {
            obb.half_extents = DVec2::new(obb.half_extents.y, obb.half_extents.x);
            obb.yaw += FRAC_PI_2;
        }
        obb.yaw = wrap_half_turn(obb.yaw);
        obb
    }

    /// Area in square metres (positive).
    pub fn area(&self) -> f64 {
        let v = &self.vertices;
        let o = v[0];
        (1..v.len() - 1).map(|i| (v[i] - o).perp_dot(v[i + 1] - o)).sum::<f64>() * 0.5
    }

    /// Centroid (centre of area), metres.
    pub fn centroid(&self) -> DVec2 {
        let v = &self.vertices;
        let o = v[0];
        let mut weighted = DVec2::ZERO;
        let mut total = 0.0;
        for i in 1..v.len() - 1 {
            let (a, b) = (v[i] - o, v[i + 1] - o);
            let w = a.perp_dot(b);
            weighted += (a + b) * w;
            total += w;
        }
        if total > 0.0 { o + weighted / (3.0 * total) } else { o }
    }

    /// The polygon moved by `offset` metres. Fails if the result leaves the supported coordinate
    /// range or collapses under rounding.
    pub fn translated(&self, offset: DVec2) -> Result<Self, GeomError> {
        let moved: Vec<DVec2> = self.vertices.iter().map(|&v| v + offset).collect();
        Self::from_loop(sanitize_all(&moved)?)
    }

    /// Minkowski sum with a disc of radius `r` metres, approximated by a polygon that contains
    /// the exact rounded shape.
    ///
    /// Each corner arc is replaced by segments tangent to the true arc (circumscribed), using
    /// about `arc_segments` segments per full turn (at least 4), so the result is a slight
    /// over-approximation; vertices are pushed out by a few ulps more so the containment survives
    /// rounding. This is the configuration-space obstacle for an agent of radius `r`. `r = 0`
    /// returns a copy; negative or non-finite `r` is an error.
    pub fn grown(&self, r: f64, arc_segments: usize) -> Result<Self, GeomError> {
        if !(r.is_finite() && r >= 0.0) {
            return Err(GeomError::InvalidParameter { what: "radius", value: r });
        }
        if r == 0.0 {
            return Ok(self.clone());
        }
        let segments = arc_segments.clamp(4, 1 << 16) as f64;
        let max_step = TAU / segments;
        let v = &self.vertices;
        let n = v.len();
        let scale = v.iter().fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()));
        let slack = 8.0 * f64::EPSILON * (r + scale);
        let mut out = Vec::new();
        for i in 0..n {
            let (prev, cur, next) = (v[(i + n - 1) % n], v[i], v[(i + 1) % n]);
            let n0 = outward_normal(prev, cur);
            let n1 = outward_normal(cur, next);
            let a0 = n0.y.atan2(n0.x);
            let turn = n0.perp_dot(n1).atan2(n0.dot(n1)).clamp(0.0, PI);
            let steps = ((turn / max_step - 1e-9).ceil() as usize).max(1);
            let step = turn / steps as f64;
            let reach = r / (step * 0.5).cos() + slack;
            for j in 0..steps {
                let angle = a0 + (j as f64 + 0.5) * step;
                out.push(cur + DVec2::from_angle(angle) * reach);
            }
        }
        // The corner arcs come out in order around a convex loop: taken as it is unless
        // rounding bent it somewhere, when the hull of the points is.
        Self::from_loop(sanitize_all(&out)?).or_else(|_| Self::hull(&out))
    }
}

/// Unit outward normal of the counter-clockwise edge `a → b`.
fn outward_normal(a: DVec2, b: DVec2) -> DVec2 {
    let e = b - a;
    DVec2::new(e.y, -e.x).normalize_or_zero()
}

/// Wraps an angle (radians) into `(-π/2, π/2]`, the symmetry range of a rectangle.
fn wrap_half_turn(a: f64) -> f64 {
    let mut w = a.rem_euclid(PI);
    if w > FRAC_PI_2 {
        w -= PI;
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    const EPS: f64 = 1e-12;

    fn v(x: f64, y: f64) -> DVec2 {
        DVec2::new(x, y)
    }

    fn unit_square() -> ConvexPolygon {
        ConvexPolygon::new(&[v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)]).unwrap()
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < EPS
    }

    #[test]
    fn unit_square_distances() {
        let s = unit_square();
        assert_eq!(s.distance(v(0.5, 0.5)), 0.0);
        assert_eq!(s.distance(v(1.0, 0.3)), 0.0);
        assert!(close(s.distance(v(2.0, 0.5)), 1.0));
        assert!(close(s.distance(v(4.0, 5.0)), 5.0));
        assert!(close(s.distance(v(-3.0, -4.0)), 5.0));
        assert!(close(s.signed_distance(v(0.5, 0.5)), -0.5));
        assert!(close(s.signed_distance(v(0.25, 0.5)), -0.25));
        assert!(close(s.signed_distance(v(0.5, 3.0)), 2.0));
        assert_eq!(s.signed_distance(v(0.0, 0.5)), 0.0);
        assert_eq!(s.closest_point(v(3.0, 0.5)), v(1.0, 0.5));
        assert_eq!(s.closest_point(v(0.2, 0.3)), v(0.2, 0.3));
        assert_eq!(s.closest_point(v(-1.0, -1.0)), v(0.0, 0.0));
        assert_eq!(s.closest_boundary_point(v(0.2, 0.5)), v(0.0, 0.5));
        assert!(s.distance(v(f64::NAN, 0.0)).is_nan());
        assert!(!s.contains(v(f64::INFINITY, 0.5)));
    }

    #[test]
    fn unit_square_measures() {
        let s = unit_square();
        assert!(close(s.area(), 1.0));
        assert!(close(s.centroid().x, 0.5) && close(s.centroid().y, 0.5));
        assert_eq!(s.aabb(), Aabb::new(v(0.0, 0.0), v(1.0, 1.0)));
        let t = s.translated(v(2.0, -1.0)).unwrap();
        assert_eq!(t.aabb(), Aabb::new(v(2.0, -1.0), v(3.0, 0.0)));
        let tri = ConvexPolygon::new(&[v(0.0, 0.0), v(3.0, 0.0), v(0.0, 3.0)]).unwrap();
        assert!(close(tri.area(), 4.5));
        assert!(close(tri.centroid().x, 1.0) && close(tri.centroid().y, 1.0));
    }

    #[test]
    fn unit_square_rays() {
        let s = unit_square();
        let hit = s.ray_cast(v(-2.0, 0.5), v(1.0, 0.0), 10.0).unwrap();
        assert!(close(hit, 2.0));
        assert_eq!(s.ray_cast(v(-2.0, 0.5), v(1.0, 0.0), 1.5), None);
        assert_eq!(s.ray_cast(v(-2.0, 0.5), v(-1.0, 0.0), 10.0), None);
        assert_eq!(s.ray_cast(v(0.5, 0.5), v(0.0, 1.0), 0.0), Some(0.0));
        // Diagonal from below-left hits the corner (0, 0) at distance sqrt(2).
        let d = s.ray_cast(v(-1.0, -1.0), v(1.0, 1.0), 10.0).unwrap();
        assert!(close(d, 2f64.sqrt()));
        // Unnormalised direction is normalised.
        assert!(close(s.ray_cast(v(0.5, 3.0), v(0.0, -5.0), 10.0).unwrap(), 2.0));
        // Grazing along the top edge.
        assert!(close(s.ray_cast(v(-1.0, 1.0), v(1.0, 0.0), 10.0).unwrap(), 1.0));
        assert_eq!(s.ray_cast(v(-1.0, 1.5), v(1.0, 0.0), 10.0), None);
        assert_eq!(s.ray_cast(v(-1.0, 0.5), DVec2::ZERO, 10.0), None);
    }

    #[test]
    fn construction_cleans_and_rejects() {
        // Clockwise input with a duplicate and a mid-edge vertex.
        let p = ConvexPolygon::new(&[v(0.0, 0.0), v(0.0, 1.0), v(0.0, 1.0), v(1.0, 1.0), v(1.0, 0.5), v(1.0, 0.0)])
            .unwrap();
        assert_eq!(p.vertices(), &[v(1.0, 0.0), v(1.0, 1.0), v(0.0, 1.0), v(0.0, 0.0)]);
        let l_shape = [v(0.0, 0.0), v(2.0, 0.0), v(2.0, 1.0), v(1.0, 1.0), v(1.0, 2.0), v(0.0, 2.0)];
        assert!(matches!(ConvexPolygon::new(&l_shape), Err(GeomError::NotConvex { .. })));
        let star: Vec<DVec2> = (0..5).map(|i| DVec2::from_angle(i as f64 * 2.0 * TAU / 5.0)).collect();
        assert!(matches!(ConvexPolygon::new(&star), Err(GeomError::NotConvex { .. })));
        assert!(matches!(ConvexPolygon::new(&[v(0.0, 0.0), v(1.0, 1.0)]), Err(GeomError::TooFewPoints { found: 2 })));
        assert!(matches!(
            ConvexPolygon::new(&[v(0.0, 0.0), v(1.0, f64::NAN), v(0.0, 1.0)]),
            Err(GeomError::NonFinite { index: 1 })
        ));
    }

    #[test]
    fn hull_of_points() {
        let pts = [
            v(0.0, 0.0),
            v(2.0, 0.0),
            v(1.0, 0.0),
            v(2.0, 2.0),
            v(1.0, 1.0),
            v(0.0, 2.0),
            v(0.5, 0.5),
            v(2.0, 2.0),
            v(0.0, 1.0),
        ];
        let h = ConvexPolygon::hull(&pts).unwrap();
        assert_eq!(h.vertices().len(), 4);
        assert!(close(h.area(), 4.0));
        assert!(pts.iter().all(|&p| h.contains(p)));
        let start = h.vertices().iter().position(|&p| p == v(0.0, 0.0)).unwrap();
        assert_eq!(h.vertices()[(start + 1) % 4], v(2.0, 0.0));
    }

    #[test]
    fn hull_errors() {
        assert_eq!(ConvexPolygon::hull(&[]), Err(GeomError::TooFewPoints { found: 0 }));
        assert_eq!(ConvexPolygon::hull(&[v(1.0, 1.0); 5]), Err(GeomError::TooFewPoints { found: 1 }));
        assert_eq!(
            ConvexPolygon::hull(&[v(0.0, 0.0), v(1.0, 1.0), v(0.0, 0.0)]),
            Err(GeomError::TooFewPoints { found: 2 })
        );
        assert_eq!(
            ConvexPolygon::hull(&[v(0.0, 0.0), v(1.0, 1.0), v(3.0, 3.0), v(-2.0, -2.0)]),
            Err(GeomError::Collinear)
        );
        assert_eq!(
            ConvexPolygon::hull(&[v(0.0, 0.0), v(1.0, 0.0), v(0.0, f64::INFINITY)]),
            Err(GeomError::NonFinite { index: 2 })
        );
        assert!(matches!(
            ConvexPolygon::hull(&[v(0.0, 0.0), v(1e16, 0.0), v(0.0, 1.0)]),
            Err(GeomError::OutOfRange { index: 1, .. })
        ));
        // Tiny coordinates are flushed to zero rather than rejected.
        let h = ConvexPolygon::hull(&[v(1e-50, 0.0), v(1.0, 0.0), v(0.0, 1.0)]).unwrap();
        assert!(h.vertices().contains(&v(0.0, 0.0)));
    }

    #[test]
    fn box_yaw() {
        let b = ConvexPolygon::from_box(v(1.0, 2.0), 4.0, 2.0, FRAC_PI_2).unwrap();
        // Width runs along +y after a quarter turn: extent 2 × 4 around (1, 2).
        let bb = b.aabb();
        assert!(close(bb.min.x, 0.0) && close(bb.max.x, 2.0));
        assert!(close(bb.min.y, 0.0) && close(bb.max.y, 4.0));
        assert!(close(b.area(), 8.0));
        let r = ConvexPolygon::from_box(DVec2::ZERO, 2.0, 2.0, PI / 4.0).unwrap();
        let s2 = 2f64.sqrt();
        assert!(close(r.aabb().max.x, s2) && close(r.aabb().min.y, -s2));
        assert!(r.contains(v(1.4, 0.0)) && !r.contains(v(1.0, 1.0)));
        assert!(matches!(
            ConvexPolygon::from_box(DVec2::ZERO, 0.0, 1.0, 0.0),
            Err(GeomError::InvalidParameter { what: "width", .. })
        ));
        assert!(ConvexPolygon::from_box(DVec2::ZERO, 1.0, 1.0, f64::NAN).is_err());
    }

    #[test]
    fn obb_of_rotated_rectangle() {
        for yaw in [0.0, 0.3, 1.2, -0.7, 2.5] {
            let rect = ConvexPolygon::from_box(v(3.0, -1.0), 4.0, 1.0, yaw).unwrap();
            let obb = rect.obb();
            assert!(close(obb.center.x, 3.0) && close(obb.center.y, -1.0), "{yaw}: {obb:?}");
            assert!(close(obb.half_extents.x, 2.0) && close(obb.half_extents.y, 0.5), "{yaw}: {obb:?}");
            assert!(close(wrap_half_turn(obb.yaw - yaw), 0.0), "{yaw}: {obb:?}");
            assert!(obb.yaw > -FRAC_PI_2 && obb.yaw <= FRAC_PI_2);
        }
        // A triangle: the optimal box is flush with one of its edges.
        let tri = ConvexPolygon::new(&[v(0.0, 0.0), v(4.0, 0.0), v(0.0, 3.0)]).unwrap();
        let obb = tri.obb();
        assert!(close(obb.area(), 12.0));
        assert!(tri.vertices().iter().all(|&p| obb.contains(p + (obb.center - p) * 1e-9)));
        let back = obb.to_polygon().unwrap();
        assert!(close(back.area(), obb.area()));
    }

    #[test]
    fn grown_square() {
        let s = unit_square();
        let g = s.grown(0.5, 16).unwrap();
        // Offset edges are exact; corners are circumscribed quarter circles with 4 segments.
        assert!(g.contains(v(1.5, 0.5)) && g.contains(v(-0.5, 0.5)));
        assert!(!g.contains(v(1.51, 0.5)));
        let corner = v(1.0, 1.0) + DVec2::from_angle(PI / 4.0) * 0.5;
        assert!(g.contains(corner));
        let exact_area = 1.0 + 4.0 * 0.5 + PI * 0.25;
        let circumscribed_area = 1.0 + 4.0 * 0.5 + 16.0 * 0.25 * (PI / 16.0).tan();
        assert!(g.area() >= exact_area);
        assert!((g.area() - circumscribed_area).abs() < 1e-9, "{}", g.area());
        assert_eq!(g.vertices().len(), 16);
        assert_eq!(s.grown(0.0, 8).unwrap(), s);
        assert!(s.grown(-1.0, 8).is_err());
        assert!(s.grown(f64::NAN, 8).is_err());
    }
}
