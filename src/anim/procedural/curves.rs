//! Key-frame curves of the procedural walk (seed 002 §4.1: key frames per step, interpolation
//! between them; DESIGN.md §4): shape-preserving cubic curves through key values, smoothstep
//! ramps, cubic Hermite bridges and the cubic Bezier curve of the swing foot.

use crate::geom::smoothstep;

/// Key values at parameters (phases or times), interpolated by a shape-preserving cubic Hermite
/// curve: tangents are harmonic means of the neighbouring slopes and zero at local extrema, so
/// the curve never overshoots its keys. Periodic curves repeat with period 1; open curves have
/// flat ends and are constant outside their keys.
#[derive(Debug, Clone)]
pub(crate) struct KeyCurve {
    keys: Vec<(f64, f64)>,
    tangents: Vec<f64>,
    periodic: bool,
}

impl KeyCurve {
    /// A curve of period 1 through `keys` (parameters taken modulo 1).
    pub(crate) fn periodic(keys: &[(f64, f64)]) -> KeyCurve {
        let mut k: Vec<(f64, f64)> = keys.iter().map(|&(p, v)| (p.rem_euclid(1.0), v)).collect();
        k.sort_by(|a, b| a.0.total_cmp(&b.0));
        KeyCurve::build(k, true)
    }

    /// A curve over `[first key, last key]` through `keys` (sorted by parameter; keys with a
    /// parameter not above the previous one are dropped), constant outside.
    pub(crate) fn open(keys: &[(f64, f64)]) -> KeyCurve {
        let mut k: Vec<(f64, f64)> = Vec::with_capacity(keys.len());
        for &key in keys {
            if k.last().is_none_or(|l: &(f64, f64)| key.0 > l.0) {
                k.push(key);
            }
        }
        KeyCurve::build(k, false)
    }

    /// A curve over `[first key, last key]` through `keys` (parameter, value, slope; sorted by
    /// parameter, keys with a parameter not above the previous one dropped) with the given
    /// slopes, constant outside.
    pub(crate) fn with_slopes(keys: &[(f64, f64, f64)]) -> KeyCurve {
        let mut k: Vec<(f64, f64, f64)> = Vec::with_capacity(keys.len());
        for &key in keys {
            if k.last().is_none_or(|l: &(f64, f64, f64)| key.0 > l.0) {
                k.push(key);
            }
        }
        KeyCurve {
            keys: k.iter().map(|&(p, v, _)| (p, v)).collect(),
            tangents: k.iter().map(|&(_, _, d)| d).collect(),
            periodic: false,
        }
    }

    /// A constant.
    pub(crate) fn constant(v: f64) -> KeyCurve {
        KeyCurve::open(&[(0.0, v)])
    }

    fn build(keys: Vec<(f64, f64)>, periodic: bool) -> KeyCurve {
        let n = keys.len();
        let key = |i: isize| -> (f64, f64) {
            let m = n as isize;
            let (p, v) = keys[i.rem_euclid(m) as usize];
            (p + i.div_euclid(m) as f64, v)
        };
        let tangents = (0..n as isize)
            .map(|i| {
                if n < 2 || !periodic && (i == 0 || i == n as isize - 1) {
                    return 0.0;
                }
                let (p0, v0) = key(i - 1);
                let (p1, v1) = key(i);
                let (p2, v2) = key(i + 1);
                let (d0, d1) = ((v1 - v0) / (p1 - p0), (v2 - v1) / (p2 - p1));
                if d0 * d1 <= 0.0 { 0.0 } else { 2.0 * d0 * d1 / (d0 + d1) }
            })
            .collect();
        KeyCurve { keys, tangents, periodic }
    }

    /// The value at parameter `x`.
    pub(crate) fn at(&self, x: f64) -> f64 {
        let n = self.keys.len();
        if n == 1 {
            return self.keys[0].1;
        }
        let (i, j, p0, p1, x) = if self.periodic {
            let x = x.rem_euclid(1.0);
            match self.keys.iter().rposition(|k| k.0 <= x) {
                Some(i) if i + 1 < n => (i, i + 1, self.keys[i].0, self.keys[i + 1].0, x),
                Some(i) => (i, 0, self.keys[i].0, self.keys[0].0 + 1.0, x),
                None => (n - 1, 0, self.keys[n - 1].0 - 1.0, self.keys[0].0, x),
            }
        } else {
            if !(x > self.keys[0].0) {
                return self.keys[0].1;
            }
            if x >= self.keys[n - 1].0 {
                return self.keys[n - 1].1;
            }
            let i = self.keys.iter().rposition(|k| k.0 <= x).unwrap_or(0).min(n - 2);
            (i, i + 1, self.keys[i].0, self.keys[i + 1].0, x)
        };
        hermite(x, p0, p1, self.keys[i].1, self.keys[j].1, self.tangents[i], self.tangents[j])
    }
}

/// The cubic Hermite curve from value `v0` with slope `d0` at `x0` to `v1` with slope `d1` at
/// `x1`, evaluated at `x` (slopes per unit of `x`).
pub(crate) fn hermite(x: f64, x0: f64, x1: f64, v0: f64, v1: f64, d0: f64, d1: f64) -> f64 {
    let h = x1 - x0;
    if !(h > 0.0) {
        return v0;
    }
    let u = (x - x0) / h;
    let (u2, u3) = (u * u, u * u * u);
    (2.0 * u3 - 3.0 * u2 + 1.0) * v0 + (u3 - 2.0 * u2 + u) * h * d0 + (-2.0 * u3 + 3.0 * u2) * v1 + (u3 - u2) * h * d1
}

/// A weight going from `from` at `t0` to `to` at `t1` along a smoothstep (times in seconds).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Ramp {
    /// Start, seconds.
    pub t0: f64,
    /// End, seconds.
    pub t1: f64,
    /// Value up to `t0`.
    pub from: f64,
    /// Value from `t1` on.
    pub to: f64,
}

impl Ramp {
    /// Always `v`.
    pub(crate) const fn constant(v: f64) -> Ramp {
        Ramp { t0: 0.0, t1: 1.0, from: v, to: v }
    }

    /// From `from` to `to` over `[t0, t1]`.
    pub(crate) const fn new(t0: f64, t1: f64, from: f64, to: f64) -> Ramp {
        Ramp { t0, t1, from, to }
    }

    /// The value at `t`.
    pub(crate) fn at(self, t: f64) -> f64 {
        let x = if self.t1 > self.t0 {
            (t - self.t0) / (self.t1 - self.t0)
        } else if t < self.t0 {
            0.0
        } else {
            1.0
        };
        self.from + (self.to - self.from) * smoothstep(x)
    }
}

/// A cubic Bezier curve in a plane, `(progress, height)`: the swing foot's curve of seed 002
/// §4.1 in the sagittal plane of its step. Progress runs from 0 (lift-off) to 1 (touch-down).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Bezier {
    /// The four control points.
    pub points: [(f64, f64); 4],
}

impl Bezier {
    /// The point at parameter `u` in `[0, 1]`.
    pub(crate) fn at(&self, u: f64) -> (f64, f64) {
        let v = 1.0 - u;
        let w = [v * v * v, 3.0 * v * v * u, 3.0 * v * u * u, u * u * u];
        let p = &self.points;
        (0..4).fold((0.0, 0.0), |(a, b), k| (a + w[k] * p[k].0, b + w[k] * p[k].1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn key_curves_pass_through_their_keys_without_overshoot() {
        let c = KeyCurve::periodic(&[(0.9, -1.0), (0.1, 0.5), (0.3, 1.0), (0.6, 0.0)]);
        for &(p, v) in &[(0.9, -1.0), (0.1, 0.5), (0.3, 1.0), (0.6, 0.0), (1.9, -1.0)] {
            assert!((c.at(p) - v).abs() < 1e-12, "{p}: {}", c.at(p));
        }
        for j in 0..=1000 {
            let v = c.at(j as f64 / 1000.0);
            assert!((-1.0..=1.0).contains(&v));
        }
        // Continuous across the wrap and monotone between keys.
        assert!((c.at(1.0 - 1e-9) - c.at(0.0)).abs() < 1e-6);
        let o = KeyCurve::open(&[(0.0, 0.0), (0.5, 1.0), (1.0, -1.0)]);
        assert_eq!((o.at(-1.0), o.at(0.5), o.at(2.0)), (0.0, 1.0, -1.0));
        assert!((0..100).all(|j| o.at(0.5 * j as f64 / 100.0) <= o.at(0.5 * (j + 1) as f64 / 100.0) + 1e-12));
        // Repeated parameters are dropped; a single key is a constant.
        let d = KeyCurve::open(&[(0.0, 1.0), (0.0, 5.0), (1.0, 2.0)]);
        assert_eq!((d.at(0.0), d.at(1.0)), (1.0, 2.0));
        // Given slopes are kept.
        let s = KeyCurve::with_slopes(&[(0.0, 0.0, 2.0), (1.0, 1.0, -1.0), (2.0, 0.5, 0.0)]);
        let h = 1e-7;
        assert!((s.at(1.0) - 1.0).abs() < 1e-12 && ((s.at(h) - s.at(0.0)) / h - 2.0).abs() < 1e-5);
        assert!(((s.at(1.0 + h) - s.at(1.0 - h)) / (2.0 * h) + 1.0).abs() < 1e-5);
        assert_eq!((s.at(-1.0), s.at(3.0)), (0.0, 0.5));
        assert_eq!(KeyCurve::constant(3.0).at(-7.0), 3.0);
    }

    #[test]
    fn hermite_bridges_match_values_and_slopes() {
        let f = |x: f64| hermite(x, 1.0, 3.0, 2.0, -1.0, 0.5, -2.0);
        assert!((f(1.0) - 2.0).abs() < 1e-12 && (f(3.0) + 1.0).abs() < 1e-12);
        let h = 1e-6;
        assert!(((f(1.0 + h) - f(1.0)) / h - 0.5).abs() < 1e-4);
        assert!(((f(3.0) - f(3.0 - h)) / h + 2.0).abs() < 1e-4);
    }

    #[test]
    fn ramps_and_bezier_ends() {
        let r = Ramp::new(1.0, 2.0, 0.0, 4.0);
        assert_eq!((r.at(0.0), r.at(1.5), r.at(3.0)), (0.0, 2.0, 4.0));
        let step = Ramp::new(1.0, 1.0, 0.0, 1.0);
        assert_eq!((step.at(0.5), step.at(1.0)), (0.0, 1.0));
        assert_eq!(Ramp::constant(0.3).at(9.0), 0.3);
        let b = Bezier { points: [(0.0, 0.0), (0.0, 1.0), (1.0, 1.0), (1.0, 0.0)] };
        assert_eq!(b.at(0.0), (0.0, 0.0));
        assert_eq!(b.at(1.0), (1.0, 0.0));
        let (p, z) = b.at(0.5);
        assert!((p - 0.5).abs() < 1e-12 && (z - 0.75).abs() < 1e-12);
    }
}
