//! Exact orientation predicate.

use std::cmp::Ordering;

use glam::DVec2;

/// Half an ulp of 1.0: the relative rounding error of one f64 operation.
const HALF_EPS: f64 = f64::EPSILON * 0.5;

/// Relative error bound of the straightforward determinant (Shewchuk's `ccwerrboundA`).
const ORIENT_ERR_BOUND: f64 = (3.0 + 16.0 * HALF_EPS) * HALF_EPS;

/// Orientation of the triangle `a`, `b`, `c` (coordinates in metres).
///
/// Returns [`Ordering::Greater`] when `c` lies strictly left of the directed line `a → b`
/// (counter-clockwise turn), [`Ordering::Less`] when it lies strictly right (clockwise turn) and
/// [`Ordering::Equal`] when the three points are collinear.
///
/// The answer is exact for finite coordinates whose magnitudes are either zero or between
/// [`super::TINY_COORDINATE`] and [`super::MAX_COORDINATE`]: a fast floating-point evaluation is
/// used when its error bound decides the sign, otherwise the determinant is summed exactly.
/// Non-finite input yields an unspecified ordering (never a panic).
pub fn orientation(a: DVec2, b: DVec2, c: DVec2) -> Ordering {
    let left = (a.x - c.x) * (b.y - c.y);
    let right = (a.y - c.y) * (b.x - c.x);
    let det = left - right;
    let bound = ORIENT_ERR_BOUND * (left.abs() + right.abs());
    if det > bound {
        return Ordering::Greater;
    }
    if -det > bound {
        return Ordering::Less;
    }
    if bound == 0.0 && det == 0.0 {
        return Ordering::Equal;
    }
    exact_orientation(a, b, c)
}

/// `a + b` as an unevaluated sum `(rounded, error)`.
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bv = s - a;
    let av = s - bv;
    (s, (a - av) + (b - bv))
}

/// `a * b` as an unevaluated sum `(rounded, error)`, exact via fused multiply-add.
fn two_product(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// Sign of the orientation determinant computed without rounding error.
///
/// Expands `(ax - cx)(by - cy) - (ay - cy)(bx - cx)` into six coordinate products (the `cx·cy`
/// terms cancel), splits each product exactly into two doubles and accumulates the twelve terms
/// into a non-overlapping expansion whose largest non-zero component carries the sign.
fn exact_orientation(a: DVec2, b: DVec2, c: DVec2) -> Ordering {
    let products = [(a.x, b.y), (-a.x, c.y), (-c.x, b.y), (-a.y, b.x), (a.y, c.x), (c.y, b.x)];
    let mut expansion = [0.0f64; 12];
    let mut len = 0;
    for (x, y) in products {
        let (p, e) = two_product(x, y);
        for term in [e, p] {
            let mut q = term;
            for component in expansion.iter_mut().take(len) {
                let (s, err) = two_sum(q, *component);
                *component = err;
                q = s;
            }
            expansion[len] = q;
            len += 1;
        }
    }
    for &component in expansion[..len].iter().rev() {
        if component > 0.0 {
            return Ordering::Greater;
        }
        if component < 0.0 {
            return Ordering::Less;
        }
    }
    Ordering::Equal
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simple_turns() {
        let a = DVec2::new(0.0, 0.0);
        let b = DVec2::new(1.0, 0.0);
        assert_eq!(orientation(a, b, DVec2::new(0.5, 1.0)), Ordering::Greater);
        assert_eq!(orientation(a, b, DVec2::new(0.5, -1.0)), Ordering::Less);
        assert_eq!(orientation(a, b, DVec2::new(7.0, 0.0)), Ordering::Equal);
    }

    #[test]
    fn nearly_collinear_points_are_decided_exactly() {
        // Points on the line y = x shifted by single ulps; the naive determinant is unreliable here.
        let a = DVec2::new(0.5, 0.5);
        let b = DVec2::new(12.0, 12.0);
        let c = DVec2::new(24.0, 24.0);
        assert_eq!(orientation(a, b, c), Ordering::Equal);
        let above = DVec2::new(0.5, 0.5f64.next_up());
        assert_eq!(orientation(b, c, above), Ordering::Greater);
        let below = DVec2::new(0.5, 0.5f64.next_down());
        assert_eq!(orientation(b, c, below), Ordering::Less);
        let far = DVec2::new(1e15, 1e15);
        let off = DVec2::new(0.1, 0.1f64.next_up());
        assert_eq!(orientation(DVec2::ZERO, far, off), Ordering::Greater);
    }
}
