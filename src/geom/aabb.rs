//! Axis-aligned bounding boxes.

use glam::DVec2;

/// Axis-aligned bounding box with corners `min` and `max`, in metres.
///
/// A box is meaningful when `min <= max` component-wise; a box with `min == max` is a point.
/// Boxes with NaN corners or `min > max` are accepted everywhere but never contain, intersect or
/// come within any distance of anything.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Lower-left corner (smallest x and y), metres.
    pub min: DVec2,
    /// Upper-right corner (largest x and y), metres.
    pub max: DVec2,
}

impl Aabb {
    /// Box with the given corners, in metres. The corners are taken as given (not sorted).
    pub const fn new(min: DVec2, max: DVec2) -> Self {
        Self { min, max }
    }

    /// Smallest box containing all `points`; `None` for an empty slice.
    pub fn from_points(points: &[DVec2]) -> Option<Self> {
        let (&first, rest) = points.split_first()?;
        Some(rest.iter().fold(Self::new(first, first), |b, &p| Self::new(b.min.min(p), b.max.max(p))))
    }

    /// Square box of half-size `radius` (metres) around `center`.
    pub fn around(center: DVec2, radius: f64) -> Self {
        Self::new(center - DVec2::splat(radius), center + DVec2::splat(radius))
    }

    /// Centre of the box, metres.
    pub fn center(&self) -> DVec2 {
        (self.min + self.max) * 0.5
    }

    /// Width and height of the box, metres.
    pub fn size(&self) -> DVec2 {
        self.max - self.min
    }

    /// Smallest box containing both boxes.
    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb::new(self.min.min(other.min), self.max.max(other.max))
    }

    /// Whether the two closed boxes share at least one point.
    pub fn intersects(&self, other: &Aabb) -> bool {
        self.min.x <= other.max.x && other.min.x <= self.max.x && self.min.y <= other.max.y && other.min.y <= self.max.y
    }

    /// Whether `p` lies in the closed box.
    pub fn contains_point(&self, p: DVec2) -> bool {
        self.min.x <= p.x && p.x <= self.max.x && self.min.y <= p.y && p.y <= self.max.y
    }

    /// Box grown by `r` metres on every side (shrunk for negative `r`).
    pub fn expanded(&self, r: f64) -> Aabb {
        Aabb::new(self.min - DVec2::splat(r), self.max + DVec2::splat(r))
    }

    /// Euclidean distance in metres from `p` to the closed box; 0 inside. NaN for a NaN point,
    /// infinity for an empty or NaN box.
    ///
    /// The result is monotone in the box: a box containing another is never farther away, even
    /// after rounding. [`super::SpatialIndex::query_circle`] relies on this.
    pub fn distance(&self, p: DVec2) -> f64 {
        if p.is_nan() {
            return f64::NAN;
        }
        if !(self.min.x <= self.max.x && self.min.y <= self.max.y) {
            return f64::INFINITY;
        }
        let dx = (self.min.x - p.x).max(p.x - self.max.x).max(0.0);
        let dy = (self.min.y - p.y).max(p.y - self.max.y).max(0.0);
        (dx * dx + dy * dy).sqrt()
    }

    /// Whether the segment `origin + t·dir`, `t ∈ [0, max_t]`, touches the closed box.
    ///
    /// `dir` need not be unit length; with a unit `dir`, `max_t` is a length in metres. A zero
    /// `dir` tests the single point `origin`. Non-finite input gives `false`.
    ///
    /// The test is monotone in the box: a box containing another is hit whenever the inner one
    /// is, even after rounding. [`super::SpatialIndex::query_ray`] relies on this.
    pub fn intersects_segment(&self, origin: DVec2, dir: DVec2, max_t: f64) -> bool {
        if !(max_t >= 0.0) {
            return false;
        }
        let mut t0 = 0.0f64;
        let mut t1 = max_t;
        for axis in 0..2 {
            let (o, d, lo, hi) = (origin[axis], dir[axis], self.min[axis], self.max[axis]);
            if !(lo <= hi) {
                return false;
            }
            if d == 0.0 {
                if !(lo <= o && o <= hi) {
                    return false;
                }
                continue;
            }
            let a = (lo - o) / d;
            let b = (hi - o) / d;
            let (near, far) = if d > 0.0 { (a, b) } else { (b, a) };
            if !(near <= far) {
                return false;
            }
            t0 = t0.max(near);
            t1 = t1.min(far);
            if t0 > t1 {
                return false;
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit() -> Aabb {
        Aabb::new(DVec2::ZERO, DVec2::ONE)
    }

    #[test]
    fn distances() {
        let b = unit();
        assert_eq!(b.distance(DVec2::new(0.5, 0.5)), 0.0);
        assert_eq!(b.distance(DVec2::new(2.0, 0.5)), 1.0);
        assert_eq!(b.distance(DVec2::new(4.0, 5.0)), 5.0);
        assert_eq!(b.distance(DVec2::new(-3.0, -4.0)), 5.0);
    }

    #[test]
    fn set_operations() {
        let b = unit();
        let c = Aabb::new(DVec2::new(1.0, 1.0), DVec2::new(2.0, 3.0));
        assert!(b.intersects(&c));
        assert!(!b.intersects(&c.expanded(-0.1)));
        assert_eq!(b.union(&c), Aabb::new(DVec2::ZERO, DVec2::new(2.0, 3.0)));
        assert!(b.contains_point(DVec2::new(1.0, 0.0)));
        assert!(!b.contains_point(DVec2::new(1.1, 0.0)));
        assert_eq!(b.expanded(1.0), Aabb::new(DVec2::splat(-1.0), DVec2::splat(2.0)));
        assert_eq!(
            Aabb::from_points(&[DVec2::new(3.0, -1.0), DVec2::new(-2.0, 4.0)]),
            Some(Aabb::new(DVec2::new(-2.0, -1.0), DVec2::new(3.0, 4.0)))
        );
        assert_eq!(Aabb::from_points(&[]), None);
    }

    #[test]
    fn segments() {
        let b = unit();
        assert!(b.intersects_segment(DVec2::new(-1.0, 0.5), DVec2::X, 1.0));
        assert!(!b.intersects_segment(DVec2::new(-1.0, 0.5), DVec2::X, 0.99));
        assert!(!b.intersects_segment(DVec2::new(-1.0, 0.5), -DVec2::X, 10.0));
        assert!(b.intersects_segment(DVec2::new(0.5, 3.0), -DVec2::Y, 2.0));
        assert!(!b.intersects_segment(DVec2::new(2.0, 3.0), -DVec2::Y, 10.0));
        assert!(b.intersects_segment(DVec2::new(0.5, 0.5), DVec2::ZERO, 0.0));
        assert!(b.intersects_segment(DVec2::new(-1.0, -1.0), DVec2::new(1.0, 1.0), 1.0));
        assert!(!b.intersects_segment(DVec2::new(-1.0, 0.5), DVec2::X, f64::NAN));
    }
}
